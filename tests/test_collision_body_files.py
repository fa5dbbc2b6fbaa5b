"""An arm's body from its files (issue 40): where each link sits in the chain's frames, body files, and a URDF's
``<collision>`` elements with an SRDF's disabled pairs.

The reference is the URDF itself, read here with ``xml.etree`` (not the parser redkin uses): a link's pose is the
product of the ``<origin>`` transforms and Rodrigues rotations about each joint's ``<axis>`` from the root down
(:func:`tests.support.urdf_reference.reference_fk`), and a collision's shape is placed by its own ``<origin>``.  The
URDFs are written here with every kind of collision at random origins, a link fixed below the base, a fixed link in
the middle of the chain, a hand and its tool-centre point fixed below the tip, a prismatic finger below the hand and a
revolute link past the tip (both off the chain), and a root link above the chain's base.
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from redkin.collision import (
    body_data,
    numbered_link_frames,
    read_body,
    srdf_ignored_pairs,
    urdf_body,
    urdf_link_frames,
)
from redkin.collision.body import posed
from redkin.errors import RobotDescriptionError
from redkin.models import pa10_7c
from tests.support.urdf_reference import reference_fk

#: The links of the written URDFs and the kinds of their collisions, in the file's order.
LINKS = {
    "world": ["box"], "base_link": ["box", "sphere"], "base_plate": ["box"], "l1": ["cylinder", "sphere"],
    "l2": ["box"], "l2_cover": ["sphere"], "l3": ["box", "cylinder"], "l4": ["sphere"], "hand": ["box", "cylinder"],
    "tcp": [], "finger": ["box"], "l5": ["sphere"],
}
#: Its joints: name, type, parent, child.  The chain runs from base_link to l4.
JOINTS = [
    ("mount", "fixed", "world", "base_link"), ("plate", "fixed", "base_link", "base_plate"),
    ("j1", "revolute", "base_link", "l1"), ("j2", "revolute", "l1", "l2"), ("cover", "fixed", "l2", "l2_cover"),
    ("j3", "continuous", "l2", "l3"), ("j4", "revolute", "l3", "l4"), ("flange", "fixed", "l4", "hand"),
    ("tcp_joint", "fixed", "hand", "tcp"), ("finger_joint", "prismatic", "hand", "finger"),
    ("j5", "revolute", "l4", "l5"),
]
#: The links fixed in the chain's frames, with their frame: the path from base_link to l4 and what hangs below it
#: through fixed joints only.
FRAMES = {"base_link": 0, "base_plate": 0, "l1": 1, "l2": 2, "l2_cover": 2, "l3": 3, "l4": 4, "hand": 4, "tcp": 4}


def _words(values) -> str:
    return " ".join(repr(float(value)) for value in values)


def _robot(seed: int) -> str:
    """A URDF of :data:`LINKS` and :data:`JOINTS` with random origins, axes, collision origins and sizes."""
    rng = np.random.default_rng(seed)

    def origin() -> str:
        return f'<origin xyz="{_words(rng.uniform(-0.3, 0.3, 3))}" rpy="{_words(rng.uniform(-np.pi, np.pi, 3))}"/>'

    def geometry(kind: str) -> str:
        if kind == "sphere":
            return f'<sphere radius="{rng.uniform(0.01, 0.2)!r}"/>'
        if kind == "cylinder":
            return f'<cylinder radius="{rng.uniform(0.01, 0.2)!r}" length="{rng.uniform(0.0, 0.5)!r}"/>'
        return f'<box size="{_words(rng.uniform(0.01, 0.5, 3))}"/>'

    links = ""
    for link, kinds in LINKS.items():
        collisions = "".join(f"<collision>{'' if link == 'base_plate' else origin()}"  # one without an origin
                             f"<geometry>{geometry(kind)}</geometry></collision>" for kind in kinds)
        links += f'<link name="{link}">{collisions}</link>'
    joints = ""
    for name, kind, parent, child in JOINTS:
        axis = rng.normal(size=3)
        limit = '<limit lower="-2" upper="2" effort="1" velocity="1"/>' if kind in ("revolute", "prismatic") else ""
        joints += (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>{origin()}'
                   f'<axis xyz="{_words(axis / np.linalg.norm(axis))}"/>{limit}</joint>')
    return f'<robot name="written">{links}{joints}</robot>'


def _write(folder: Path, seed: int) -> tuple[Path, str]:
    text = _robot(seed)
    path = folder / "arm.urdf"
    path.write_text(text)
    return path, text


def _transform(origin) -> np.ndarray:
    """An ``<origin>`` element as a 4x4 (rpy: Rz(yaw) Ry(pitch) Rx(roll), scipy's extrinsic xyz)."""
    pose = np.eye(4)
    if origin is not None:
        pose[:3, :3] = Rotation.from_euler("xyz", [float(v) for v in origin.get("rpy").split()]).as_matrix()
        pose[:3, 3] = [float(v) for v in origin.get("xyz").split()]
    return pose


def _link_pose(text: str, q: np.ndarray, link: str) -> np.ndarray:
    """Link ``link``'s pose in base_link's coordinates at chain joint values ``q``, from the URDF's definition."""
    return np.linalg.inv(reference_fk(text, q, "base_link")) @ reference_fk(text, q, link)


def _collisions(text: str, q: np.ndarray) -> list[tuple[str, str, np.ndarray, np.ndarray]]:
    """Per collision of a covered link, in the file's order: its link, kind, pose in base_link's
    coordinates at ``q``, and sizes (a sphere's radius; a cylinder's radius and length; a box's edges)."""
    found = []
    for link in ET.fromstring(text).findall("link"):
        if link.get("name") not in FRAMES:
            continue
        pose = _link_pose(text, q, link.get("name"))
        for collision in link.findall("collision"):
            shape = collision.find("geometry")[0]
            sizes = {"sphere": lambda s: [s.get("radius")], "cylinder": lambda s: [s.get("radius"), s.get("length")],
                     "box": lambda s: s.get("size").split()}[shape.tag](shape)
            found.append((link.get("name"), shape.tag, pose @ _transform(collision.find("origin")),
                          np.array(sizes, dtype=float)))
    return found


def _expected_capsule(kind: str, place: np.ndarray, sizes: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The capsule the module docstring of redkin.collision.urdf_body promises for one collision, placed."""
    half = np.zeros(3)
    if kind == "sphere":
        radius = sizes[0]
    elif kind == "cylinder":
        radius, half[2] = sizes[0], sizes[1] / 2
    else:
        longest = int(np.argmax(sizes))
        half[longest] = sizes[longest] / 2
        radius = np.sqrt(np.sum(np.delete(sizes, longest) ** 2)) / 2
    return place[:3, :3] @ -half + place[:3, 3], place[:3, :3] @ half + place[:3, 3], radius


def _distance_to_segment(points: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    along = b - a
    t = np.clip((points - a) @ along / max(along @ along, 1e-300), 0.0, 1.0)
    return np.linalg.norm(points - (a + t[:, None] * along), axis=1)


# ----------------------------------------------------------------------------- link frames
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_each_link_sits_in_its_chain_frame_where_the_urdf_puts_it(tmp_path_factory, seed):
    path, text = _write(tmp_path_factory.mktemp("urdf"), seed)
    chain, links = urdf_link_frames(path, "base_link", "l4")
    assert {name: link.frame for name, link in links.items()} == FRAMES  # no finger, no l5, nothing above the base
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (5, chain.n))
    frames = chain.frames(q)
    for name, (frame, pose) in links.items():
        assert pose.shape == (4, 4) and not pose.flags.writeable
        expected = np.array([_link_pose(text, row, name) for row in q])
        np.testing.assert_allclose(frames[:, frame] @ pose, expected, rtol=0, atol=1e-12, err_msg=name)


def test_a_sub_chain_of_a_shipped_urdf_maps_its_own_links_only():
    """panda.urdf from link 2 to link 6: those links, each where the file puts it relative to link 2."""
    text = Path(__file__).resolve().parents[1].joinpath("src", "redkin", "examples", "panda.urdf").read_text()
    chain, links = urdf_link_frames("examples/panda.urdf", "panda_link2", "panda_link6")
    assert {name: link.frame for name, link in links.items()} == {f"panda_link{k}": k - 2 for k in range(2, 7)}
    q = np.random.default_rng(4).uniform(-2, 2, (5, 7))
    for name, (frame, pose) in links.items():
        expected = [np.linalg.inv(reference_fk(text, row, "panda_link2")) @ reference_fk(text, row, name) for row in q]
        np.testing.assert_allclose(chain.frames(q[:, 2:6])[:, frame] @ pose, expected, atol=1e-12)


def test_xacro_arguments_reach_the_links_and_an_unused_one_warns_once():
    _, with_hand = urdf_link_frames("examples/fr3.urdf.xacro")
    assert with_hand["fr3_hand_tcp"].frame == with_hand["fr3_hand"].frame == 7
    with pytest.warns(UserWarning, match="neither declares nor reads") as caught:
        chain, flange = urdf_link_frames("examples/fr3.urdf.xacro", xacro_args={"hand": False, "colour": "red"})
    assert len(caught) == 1 and "fr3_hand" not in flange and flange["fr3_link8"].frame == chain.n == 7


def test_a_chain_without_link_names_has_numbered_links_at_its_frames():
    chain = pa10_7c()
    links = numbered_link_frames(chain)
    assert list(links) == [f"link_{k}" for k in range(8)]
    for k, (frame, pose) in enumerate(links.values()):
        assert frame == k and not pose.flags.writeable
        np.testing.assert_array_equal(pose, np.eye(4))


# ----------------------------------------------------------------------------- the body of a URDF
@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_posed_capsules_are_the_urdf_collisions_covered_as_documented(tmp_path_factory, seed):
    """Spheres exactly, cylinders and boxes by the documented capsules, at random joint values; the finger,
    the link past the tip and the root above the base left out."""
    path, text = _write(tmp_path_factory.mktemp("urdf"), seed)
    chain, body = urdf_body(path, "base_link", "l4")
    q = np.random.default_rng(seed).uniform(-np.pi, np.pi, (4, chain.n))
    rows = posed(body, chain.frames(q))
    for row_q, rows_q in zip(q, rows):
        collisions = _collisions(text, row_q)
        assert body.link == tuple(link for link, *_ in collisions)
        assert body.frame.tolist() == [FRAMES[link] for link, *_ in collisions]
        for (link, kind, place, sizes), row in zip(collisions, rows_q):
            a, b, radius = _expected_capsule(kind, place, sizes)
            np.testing.assert_allclose(row[2:5], a, rtol=0, atol=1e-12, err_msg=f"{link} {kind}")
            np.testing.assert_allclose(row[5:8], b, rtol=0, atol=1e-12, err_msg=f"{link} {kind}")
            assert row[1] == pytest.approx(radius, rel=1e-15)
            if kind == "sphere":  # exact: a point where the product of the URDF's transforms puts the centre
                assert row[1] == sizes[0]
                np.testing.assert_array_equal(row[2:5], row[5:8])
                np.testing.assert_allclose(row[2:5], place[:3, 3], rtol=0, atol=1e-12)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_each_box_and_cylinder_lies_inside_its_capsule(tmp_path_factory, seed):
    """Random points inside each box and cylinder are inside the capsule that covers it, and its corners (rims) are
    on the capsule's surface: no smaller radius covers it."""
    path, text = _write(tmp_path_factory.mktemp("urdf"), seed)
    chain, body = urdf_body(path, "base_link", "l4")
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, chain.n)
    rows = posed(body, chain.frames(q))
    for (link, kind, place, sizes), row in zip(_collisions(text, q), rows):
        if kind == "box":
            inside = (rng.uniform(-0.5, 0.5, (300, 3))) * sizes
            edge = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]) * sizes
        elif kind == "cylinder":
            angle, reach = rng.uniform(0, 2 * np.pi, 300), sizes[0] * np.sqrt(rng.uniform(0, 1, 300))
            along = rng.uniform(-0.5, 0.5, 300) * sizes[1]
            inside = np.column_stack([reach * np.cos(angle), reach * np.sin(angle), along])
            turn = rng.uniform(0, 2 * np.pi, 8)
            edge = np.column_stack([sizes[0] * np.cos(turn), sizes[0] * np.sin(turn), np.repeat([-0.5, 0.5], 4)
                                    * sizes[1]])
        else:
            continue
        world = inside @ place[:3, :3].T + place[:3, 3]
        assert np.all(_distance_to_segment(world, row[2:5], row[5:8]) <= row[1] + 1e-12), (link, kind)
        rim = edge @ place[:3, :3].T + place[:3, 3]
        np.testing.assert_allclose(_distance_to_segment(rim, row[2:5], row[5:8]), row[1], rtol=0, atol=1e-12)


def test_the_notes_name_what_is_over_approximated_and_what_is_left_out(tmp_path):
    path, _ = _write(tmp_path, 3)
    _, body = urdf_body(path, "base_link", "l4")
    assert all("\n" not in note for note in body.notes)
    kinds = [kind for link in FRAMES for kind in LINKS[link]]
    assert sum("cylinder covered by a capsule" in note for note in body.notes) == kinds.count("cylinder")
    assert sum("box" in note and "beyond the box" in note for note in body.notes) == kinds.count("box")
    assert body.notes[-1].startswith("links world, finger, l5 not covered") and body.source == str(path)


def test_a_collision_with_a_negative_size_is_one_line_naming_the_link(tmp_path):
    text = _robot(5).replace('<box size="', '<box size="-', 1)  # the world's box, off the chain: never read
    text = text.replace('<link name="l2"><collision>', '<link name="l2"><collision><geometry><sphere radius="-0.1"/>'
                        '</geometry></collision><collision>')
    (tmp_path / "arm.urdf").write_text(text)
    with pytest.raises(RobotDescriptionError) as caught:
        urdf_body(tmp_path / "arm.urdf", "base_link", "l4")
    message = str(caught.value)
    assert "link 'l2' collision 1: sphere radius must be a finite number >= 0" in message and "\n" not in message
    assert caught.value.key == "l2"


# ----------------------------------------------------------------------------- SRDF
def _srdf(folder: Path, body: str) -> Path:
    path = folder / "arm.srdf"
    path.write_text(f'<?xml version="1.0"?>\n<robot name="written">{body}</robot>')
    return path


def test_srdf_pairs_drop_out_of_the_checked_pairs(tmp_path):
    path, _ = _write(tmp_path, 8)
    srdf = _srdf(tmp_path, '<group name="arm"><chain base_link="base_link" tip_link="l4"/></group>'
                           '<disable_collisions link1="l3" link2="l1" reason="Never"/>'
                           '<disable_collisions link1="finger" link2="l2" reason="Never"/>')  # finger: not in the body
    assert srdf_ignored_pairs(srdf) == [("l3", "l1"), ("finger", "l2")]
    _, every = urdf_body(path, "base_link", "l4")
    _, fewer = urdf_body(path, "base_link", "l4", srdf=srdf)
    named = {tuple(pair) for pair in every.pairs.tolist() if {every.link[pair[0]], every.link[pair[1]]} == {"l1", "l3"}}
    assert len(named) == len(LINKS["l1"]) * len(LINKS["l3"])  # each of l3's capsules against each of l1's
    assert {tuple(pair) for pair in fewer.pairs.tolist()} == {tuple(pair) for pair in every.pairs.tolist()} - named
    assert fewer.link == every.link and str(srdf) in fewer.source


@pytest.mark.parametrize("text, fragment", [
    ("<robot><disable_collisions link1='l1'/></robot>", "<disable_collisions> 1 needs both link1 and link2"),
    ("<robot><disable_collisions link1='l1' link2='l9'/></robot>", "names link 'l9', which the URDF"),
    ("<robot><disable_collisions link1='l1' link2='l3'>", "not XML (line 1)"),
    ("<srdf/>", "its root element is <srdf>, not <robot>"),
])
def test_a_bad_srdf_is_one_line(tmp_path, text, fragment):
    path, _ = _write(tmp_path, 9)
    (tmp_path / "arm.srdf").write_text(text)
    with pytest.raises(RobotDescriptionError) as caught:
        urdf_body(path, "base_link", "l4", srdf=tmp_path / "arm.srdf")
    message = str(caught.value)
    assert message.startswith(f"SRDF {str(tmp_path / 'arm.srdf')!r}: ") and fragment in message
    assert "\n" not in message
    with pytest.raises(RobotDescriptionError, match="cannot read it"):
        srdf_ignored_pairs(tmp_path / "missing.srdf")


# ----------------------------------------------------------------------------- body files
_NAMES = [f"link_{k}" for k in range(8)]
_point = st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3)
_radius = st.floats(0.0, 0.3)
_spheres = st.dictionaries(st.sampled_from(_NAMES), st.lists(st.fixed_dictionaries({"center": _point,
                                                                                   "radius": _radius}), max_size=3),
                           max_size=4)
_capsules = st.dictionaries(st.sampled_from(_NAMES), st.lists(st.fixed_dictionaries({"a": _point, "b": _point,
                                                                                    "radius": _radius}), max_size=3),
                            max_size=4)
_ignore = st.lists(st.lists(st.sampled_from(_NAMES), min_size=2, max_size=2), max_size=4)


@settings(max_examples=40, deadline=None)
@given(spheres=_spheres, capsules=_capsules, ignore=_ignore, as_json=st.booleans())
def test_a_written_body_file_reads_back(tmp_path_factory, spheres, capsules, ignore, as_json):
    """On a chain without link names (each link its own frame) the body is the file: spheres, then capsules, in
    the file's order; every pair checked but the same link's, neighbouring frames' and the ignored ones."""
    chain = pa10_7c()
    data = {"spheres": spheres, "capsules": capsules, "ignore": ignore}
    path = tmp_path_factory.mktemp("body") / ("arm.json" if as_json else "arm.yaml")
    path.write_text(json.dumps(data) if as_json else yaml.safe_dump(data, sort_keys=False))
    body = read_body(path, chain, numbered_link_frames(chain))
    written = ([(link, s["center"], s["center"], s["radius"]) for link, shapes in spheres.items() for s in shapes]
               + [(link, c["a"], c["b"], c["radius"]) for link, shapes in capsules.items() for c in shapes])
    assert body.link == tuple(link for link, *_ in written) and body.source == str(path) and body.notes == ()
    assert body.frame.tolist() == [int(link.split("_")[1]) for link, *_ in written]
    np.testing.assert_array_equal(body.a.reshape(-1, 3), np.array([a for _, a, _, _ in written]).reshape(-1, 3))
    np.testing.assert_array_equal(body.b.reshape(-1, 3), np.array([b for _, _, b, _ in written]).reshape(-1, 3))
    np.testing.assert_array_equal(body.radius, [radius for *_, radius in written])
    skipped = {frozenset(pair) for pair in ignore}
    expected = [(i, j) for i in range(len(written)) for j in range(i + 1, len(written))
                if abs(body.frame[i] - body.frame[j]) > 1 and body.link[i] != body.link[j]
                and frozenset((body.link[i], body.link[j])) not in skipped]
    assert body.pairs.tolist() == [list(pair) for pair in expected]


def test_a_body_file_on_urdf_links_is_posed_where_the_urdf_puts_its_links(tmp_path):
    path, text = _write(tmp_path, 11)
    chain, links = urdf_link_frames(path, "base_link", "l4")
    centres = {"base_plate": [0.1, 0.0, -0.05], "l2_cover": [0.0, 0.2, 0.0], "hand": [0.0, 0.0, 0.12]}
    body = body_data({"spheres": {link: [{"center": centre, "radius": 0.05}] for link, centre in centres.items()},
                      "capsules": {"l3": [{"a": [0, 0, 0], "b": [0.3, 0, 0.1], "radius": 0.04}]}}, chain, links)
    q = np.random.default_rng(2).uniform(-np.pi, np.pi, (6, chain.n))
    rows = posed(body, chain.frames(q))
    for row_q, rows_q in zip(q, rows):
        ends = [(_link_pose(text, row_q, link) @ [*centre, 1])[:3] for link, centre in centres.items()]
        ends += [(_link_pose(text, row_q, "l3") @ point)[:3] for point in ([0, 0, 0, 1], [0.3, 0, 0.1, 1])]
        np.testing.assert_allclose(rows_q[:, 2:5], ends[:3] + [ends[3]], rtol=0, atol=1e-12)
        np.testing.assert_allclose(rows_q[:, 5:8], ends[:3] + [ends[4]], rtol=0, atol=1e-12)


_GOOD_SPHERE = {"center": [0, 0, 0.1], "radius": 0.05}


@pytest.mark.parametrize("data, field, fragment", [
    ([], "", "expected a mapping with spheres, capsules, ignore or notes"),
    ({"sphere": {}}, "sphere", "unknown key 'sphere'"),
    ({"spheres": [_GOOD_SPHERE]}, "spheres", "spheres must be a mapping of link names to lists of spheres"),
    ({"spheres": {"link_9": [_GOOD_SPHERE]}}, "link_9", "spheres: unknown link 'link_9' (links: link_0, link_1,"),
    ({"spheres": {"link_1": _GOOD_SPHERE}}, "link_1", "spheres: link 'link_1': expected a list of spheres"),
    ({"spheres": {"link_1": ["ball"]}}, "link_1", "link 'link_1': sphere 1 must be a mapping of center, radius"),
    ({"spheres": {"link_1": [_GOOD_SPHERE, {"centre": [0, 0, 0], "radius": 1}]}}, "centre",
     "link 'link_1': sphere 2: unknown field 'centre' (a sphere has center, radius)"),
    ({"spheres": {"link_1": [{"center": [0, 0, 0]}]}}, "radius", "sphere 1: missing field 'radius'"),
    ({"spheres": {"link_1": [{"center": [0, 0], "radius": 1}]}}, "center", "sphere 1: center must have shape"),
    ({"spheres": {"link_1": [{"center": "up", "radius": 1}]}}, "center",
     "sphere 1: center must be three numbers, got 'up'"),
    ({"spheres": {"link_1": [{"center": [0, 0, float("nan")], "radius": 1}]}}, "center", "center must be finite"),
    ({"spheres": {"link_1": [{"center": [0, 0, 0], "radius": -0.1}]}}, "radius",
     "radius must be a finite number >= 0, got -0.1"),
    ({"spheres": {"link_1": [{"center": [0, 0, 0], "radius": "big"}]}}, "radius", "radius must be a number >= 0"),
    ({"spheres": {"link_1": [{"center": [0, 0, 0], "radius": True}]}}, "radius", "radius must be a number >= 0"),
    ({"spheres": {"link_1": [{"center": [0, True, 0], "radius": 1}]}}, "center", "center must be three numbers"),
    ({"capsules": {"link_2": [{"a": [0, 0, 0], "radius": 0.1}]}}, "b", "capsule 1: missing field 'b'"),
    ({"capsules": {"link_2": [{"a": [[0, 0, 0]], "b": [0, 0, 1], "radius": 0.1}]}}, "a",
     "capsule 1: a must be three numbers"),
    ({"ignore": "link_1 link_3"}, "ignore", "ignore must be a list of link pairs"),
    ({"ignore": [["link_1", "link_3", "link_5"]]}, "ignore", "ignore: entry 1 must be two link names"),
    ({"ignore": [["link_1", "link_3"], ["link_1", "hand"]]}, "hand", "ignore: entry 2: unknown link 'hand'"),
    ({"notes": "measured"}, "notes", "notes must be a list of lines of text"),
    ({"notes": ["measured", 3]}, "notes", "notes must be a list of lines of text"),
])
def test_a_bad_body_file_is_one_line_naming_the_file_the_entry_and_the_field(data, field, fragment):
    chain = pa10_7c()
    with pytest.raises(RobotDescriptionError) as caught:
        body_data(data, chain, numbered_link_frames(chain), "arm.yaml")
    message = str(caught.value)
    assert message.startswith("body file 'arm.yaml': ") and fragment in message and "\n" not in message
    assert caught.value.key == field and field in message and caught.value.path == "arm.yaml"


def test_a_body_files_notes_become_the_bodys():
    chain = pa10_7c()
    body = body_data({"spheres": {"link_7": [_GOOD_SPHERE]}, "notes": ["measured off the arm", "hand left out"]},
                     chain, numbered_link_frames(chain), "arm.yaml")
    assert body.notes == ("measured off the arm", "hand left out")


def test_a_body_file_that_is_missing_or_not_yaml_is_one_line(tmp_path):
    chain = pa10_7c()
    with pytest.raises(RobotDescriptionError, match=r"body file .*cannot read it"):
        read_body(tmp_path / "missing.yaml", chain, numbered_link_frames(chain))
    broken = tmp_path / "broken.yaml"
    broken.write_text("spheres: {link_1: [\n")
    with pytest.raises(RobotDescriptionError, match=r"body file .*not YAML or JSON at line"):
        read_body(broken, chain, numbered_link_frames(chain))


def test_a_urdf_pair_whose_capsules_always_overlap_is_not_checked_and_is_named(tmp_path):
    """Two balls round a shared axis always overlap, whatever the joints: checked, they would remove every
    configuration, so the pair is left out with a note (MoveIt's 'always in collision'); the others stay."""
    from redkin.collision.clearance import pair_table
    from redkin.collision.scene import scene_of

    joints = "".join(f'<joint name="j{k}" type="revolute"><parent link="l{k - 1}"/><child link="l{k}"/>'
                     f'<origin xyz="0 0 0.1"/><axis xyz="{"0 0 1" if k % 2 else "0 1 0"}"/>'
                     '<limit lower="-2" upper="2" effort="1" velocity="1"/></joint>' for k in range(1, 5))
    ball = '<collision><origin xyz="{x} 0 0"/><geometry><sphere radius="{r}"/></geometry></collision>'
    links = {"l0": "", "l1": ball.format(x=0, r=0.4), "l2": "", "l3": ball.format(x=0, r=0.4),
             "l4": ball.format(x=1.0, r=0.05)}
    path = tmp_path / "balls.urdf"
    elements = "".join(f'<link name="{name}">{collision}</link>' for name, collision in links.items())
    path.write_text(f'<robot name="balls">{elements}{joints}</robot>')
    chain, body = urdf_body(path, "l0", "l4")
    names = {(body.link[i], body.link[j]) for i, j in body.pairs.tolist()}
    assert ("l1", "l3") not in names and ("l1", "l4") in names
    assert any(note.startswith("link pair l1 - l3: the capsules overlap in every one of 1000") for note in body.notes)
    q = np.random.default_rng(4).uniform(-2, 2, (500, chain.n))
    apart, _ = pair_table(chain, body, scene_of({"obstacles": []}), q)
    assert np.all(apart.max(axis=0) >= 0.0)  # every pair still checked is apart somewhere
