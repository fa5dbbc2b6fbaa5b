"""The makers' Gen3 and xArm7 written out as example files (``examples/gen3.urdf``, ``examples/xarm7.urdf``).

Laws:

- FK of :func:`redkin.urdf.load_urdf` equals the product of the file's own ``<origin>`` transforms and axis
  rotations, read with ``xml.etree`` (:func:`tests.support.urdf_reference.reference_fk`), for random in-limit q;
- the limits are the file's (continuous joints unlimited), and those of the named models;
- the named models (``kinova-gen3``, ``ufactory-xarm7``) are the files with the makers' printed right angles
  (1.5708, 3.1416 and CAD residues such as 2.7629E-18) taken exact: equal to 1e-12 then; with the printed
  numbers as they stand, the two differ by the rounding alone (about 1e-5 m and rad).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin.models import get_robot
from redkin.so3 import matrix_to_axis_angle
from redkin.urdf import load_urdf
from tests.support.urdf_reference import reference_fk

EXAMPLES = Path(__file__).resolve().parents[1] / "src" / "redkin" / "examples"
# file, its tip link (the default: the only leaf), and the named model of the same arm in the same frames
ARMS = {
    "gen3": (EXAMPLES / "gen3.urdf", "tool_frame", "kinova-gen3"),
    "xarm7": (EXAMPLES / "xarm7.urdf", "link_eef", "ufactory-xarm7"),
}
UNLIMITED_SPAN = 2.0 * np.pi  # where a joint is continuous, q is drawn from +-2 pi


def _in_limits(chain, fractions) -> np.ndarray:
    """The joint vector at ``fractions`` (in [0, 1]) of each joint's range (+-2 pi for a continuous joint)."""
    lower = np.where(np.isfinite(chain.lower), chain.lower, -UNLIMITED_SPAN)
    upper = np.where(np.isfinite(chain.upper), chain.upper, UNLIMITED_SPAN)
    return lower + np.asarray(fractions) * (upper - lower)


def _file_limits(text: str) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper limits of the moving joints, straight from the XML (continuous: unlimited)."""
    lower, upper = [], []
    for joint in ET.fromstring(text).findall("joint"):
        if joint.get("type") == "continuous":
            lower.append(-np.inf)
            upper.append(np.inf)
        elif joint.get("type") == "revolute":
            limit = joint.find("limit")
            lower.append(float(limit.get("lower")))
            upper.append(float(limit.get("upper")))
    return np.array(lower), np.array(upper)


def _right_angles_exact(text: str) -> str:
    """The URDF with every ``rpy`` value within 1e-4 of a multiple of pi/2 written as that multiple, in full."""
    root = ET.fromstring(text)
    for origin in root.iter("origin"):
        values = []
        for value in (float(v) for v in origin.get("rpy", "0 0 0").split()):
            quarter = round(value / (np.pi / 2))
            values.append(repr(quarter * (np.pi / 2)) if abs(value - quarter * np.pi / 2) < 1e-4 else repr(value))
        origin.set("rpy", " ".join(values))
    return ET.tostring(root, encoding="unicode")


fractions = st.lists(st.floats(0.0, 1.0), min_size=7, max_size=7)


@pytest.mark.parametrize("arm", ARMS)
@settings(max_examples=40, deadline=None)
@given(fractions=fractions)
def test_fk_is_the_product_of_the_files_origins_and_axis_rotations(arm, fractions):
    path, tip, _ = ARMS[arm]
    chain = load_urdf(path)
    q = _in_limits(chain, fractions)
    assert chain.within_limits(q)
    np.testing.assert_allclose(chain.fk(q), reference_fk(path.read_text(), q, tip), rtol=0, atol=1e-12)


@pytest.mark.parametrize("arm", ARMS)
def test_limits_are_the_files_and_the_models(arm):
    path, _, model = ARMS[arm]
    chain = load_urdf(path)
    lower, upper = _file_limits(path.read_text())
    np.testing.assert_array_equal(chain.lower, lower)
    np.testing.assert_array_equal(chain.upper, upper)
    np.testing.assert_array_equal(chain.limits, get_robot(model).limits)  # the files print 2 pi and pi in full
    assert chain.n == 7


@pytest.mark.parametrize("arm", ARMS)
def test_the_file_with_its_right_angles_exact_is_the_named_model(arm, tmp_path):
    """The models take the makers' 1.5708 and 3.1416 as pi/2 and pi: so written, the file is the model to 1e-12,
    through redkin's URDF import and through the reference product alike."""
    path, tip, model = ARMS[arm]
    exact = _right_angles_exact(path.read_text())
    (tmp_path / path.name).write_text(exact)
    chain, named = load_urdf(tmp_path / path.name), get_robot(model)
    q = _in_limits(chain, np.random.default_rng(11).uniform(0.0, 1.0, (200, 7)))
    np.testing.assert_allclose(chain.fk(q), named.fk(q), rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.array([reference_fk(exact, row, tip) for row in q[:20]]), named.fk(q[:20]),
                               rtol=0, atol=1e-12)


@pytest.mark.parametrize("arm", ARMS)
def test_the_printed_right_angles_are_all_that_separates_file_and_model(arm):
    """With the makers' numbers as printed, the file's tool is a few micrometres and microradians from the model's:
    the rounding of pi/2 to 1.5708 (3.7e-6 rad at each of the seven joints) times the arm's lengths."""
    path, _, model = ARMS[arm]
    chain, named = load_urdf(path), get_robot(model)
    q = _in_limits(chain, np.random.default_rng(12).uniform(0.0, 1.0, (500, 7)))
    ours, theirs = chain.fk(q), named.fk(q)
    position = np.linalg.norm(ours[:, :3, 3] - theirs[:, :3, 3], axis=-1)
    _, rotation = matrix_to_axis_angle(np.swapaxes(theirs[:, :3, :3], -1, -2) @ ours[:, :3, :3])
    assert position.max() < 3e-5 and rotation.max() < 5e-5
    assert position.max() > 1e-7  # not equal: the files keep the makers' digits
