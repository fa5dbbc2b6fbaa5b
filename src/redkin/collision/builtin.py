"""The built-in bodies of the named models (issue 40): capsules fitted to each maker's collision meshes, shipped as
body files in ``redkin/collision/bodies`` and used where a named model is given a scene without a body file.

Each file was written by ``tools/builtin_bodies.py`` from the maker's description: the meshes covered as
:func:`redkin.collision.urdf_body` covers them (:mod:`redkin.collision.mesh_cover`), carried from the maker's link
frames into the named model's frames ``link_0 .. link_7`` (the two turn alike: the same joint values, zeros and
directions, checked at random joint values), with the link pairs that MoveIt's setup assistant would disable (their
meshes never, or always, meet in 20 000 random configurations within the limits, measured with coal) ignored.  Its
header lists, per link pair, how often the meshes and the capsules meet; its notes (the body's) say how far the
capsules reach beyond the meshes, and name a pair whose capsules meet far more often than its meshes.

Models without a maker's mesh description here (the PA10, the WAMs, the humanoid, the xArm7) have none: give them a
body file.
"""

from __future__ import annotations

from pathlib import Path

from redkin.chain import SerialChain
from redkin.collision.body import Body
from redkin.collision.body_file import read_body
from redkin.collision.link_frames import numbered_link_frames
from redkin.errors import RedkinError

#: Where the body files are, one per model, named after it.
_FOLDER = Path(__file__).parent / "bodies"


def builtin_models() -> tuple[str, ...]:
    """The named models that have a built-in body, sorted."""
    return tuple(sorted(path.stem for path in _FOLDER.glob("*.yaml")))


def builtin_body(model: str, chain: SerialChain) -> Body:
    """The built-in body of the named model ``model`` (``redkin robots`` names them) on its chain.

    Raises
    ------
    RedkinError
        For a model without one, naming those that have one.
    """
    file = _FOLDER / f"{model.lower()}.yaml"
    if not file.is_file():
        raise RedkinError(f"{model!r} has no built-in body (the models with one: {', '.join(builtin_models())}); "
                          "give a body file")
    return read_body(file, chain, numbered_link_frames(chain))
