"""Write the built-in bodies of the named models (src/redkin/collision/bodies/*.yaml) from the makers' descriptions.

Each body is redkin's own covering of the maker's collision meshes (:func:`redkin.collision.urdf_body`: one to three
capsules per mesh), carried from the maker's link frames into the named model's chain frames ``link_0 .. link_7``.
A named model turns its frames exactly as the maker's URDF turns its links (the same joint values, zero and
directions), so each frame differs from the URDF chain's by a constant transform; the script measures it at random
joint values and refuses to write a body where it is not constant.

The link pairs whose meshes never meet, or always meet, at :data:`SAMPLES` random configurations within the limits
(measured with coal on the maker's meshes) are ignored, as MoveIt's setup assistant disables "never in collision"
and "always in collision" pairs; the file's header lists every pair with how often its meshes and its capsules
meet, and every other pair is checked.

Usage (the makers' repositories checked out, each below one folder)::

    python tools/builtin_bodies.py MAKERS_FOLDER

    python tools/builtin_bodies.py MAKERS_FOLDER MODEL ...   # only these

MAKERS_FOLDER holds franka_description (github.com/frankaemika/franka_description), iiwa_description (from
github.com/IFL-CAMP/iiwa_stack), kortex_description (github.com/Kinovarobotics/ros_kortex), barrett_model
(github.com/jhu-lcsr/barrett_model: the WAM description of RE2 and JHU LCSR, from Barrett's CAD; its ``models``
folder and ``package.xml``) and xarm_description (from github.com/xArm-Developer/xarm_ros2, whose xArm7 collision
meshes are its visual STLs; xarm_ros's are not in its repository).  barrett_model and xarm_description's xarm7
have macros only: the script expands its own file calling them (:data:`CALLERS`), with MAKERS_FOLDER as the
package path.
"""

from __future__ import annotations

import re
import sys
import tempfile
from pathlib import Path

import numpy as np
import yaml

import redkin
from redkin.collision import body_data, numbered_link_frames, scene_of, urdf_body
from redkin.collision.clearance import pair_table

#: How far from constant the transforms between the maker's frames and the named model's may be (entries of 4x4s,
#: metres for the translations): a named model's lengths are its source's, which may round the maker's URDF.
SPREAD = 1e-4
#: Random configurations within the limits over which a pair must overlap to be ignored.
SAMPLES = 20_000

#: A pair whose capsules overlap in more of the samples than its meshes by this share is named in the body's notes.
WORTH_SAYING = 0.05
#: Per named model: the maker's description below MAKERS_FOLDER, its xacro arguments, base and tip links, and where
#: the description comes from.
SOURCES = {
    "franka-panda": ("franka_description/robots/fer/fer.urdf.xacro", {"hand": "false"}, None, None,
                     "franka_description (github.com/frankaemika/franka_description), robots/fer, without a hand"),
    "franka-fr3": ("franka_description/robots/fr3/fr3.urdf.xacro", {"hand": "false"}, None, None,
                   "franka_description (github.com/frankaemika/franka_description), robots/fr3, without a hand"),
    "kuka-iiwa14": ("iiwa_description/urdf/iiwa14.urdf.xacro", {}, "iiwa_link_0", "iiwa_link_ee",
                    "iiwa_description of iiwa_stack (github.com/IFL-CAMP/iiwa_stack), iiwa14"),
    "kuka-iiwa7": ("iiwa_description/urdf/iiwa7.urdf.xacro", {}, "iiwa_link_0", "iiwa_link_ee",
                   "iiwa_description of iiwa_stack (github.com/IFL-CAMP/iiwa_stack), iiwa7"),
    "kinova-gen3": ("kortex_description/arms/gen3/7dof/urdf/GEN3-7DOF-NOVISION_FOR_URDF_ARM_V12.urdf", {},
                    "base_link", "end_effector_link",
                    "kortex_description of ros_kortex (github.com/Kinovarobotics/ros_kortex), gen3 7dof without "
                    "vision"),
    "barrett-wam7": ("barrett-wam7.urdf.xacro", {}, "wam/base_link", "wam/wrist_palm_stump_link",
                     "barrett_model (github.com/jhu-lcsr/barrett_model, RE2's WAM URDF from Barrett's CAD), "
                     "wam_7dof without a hand"),
    "ufactory-xarm7": ("ufactory-xarm7.urdf.xacro", {}, "link_base", "link_eef",
                       "xarm_description of xarm_ros2 (github.com/xArm-Developer/xarm_ros2), xarm7 without a gripper"),
}
#: Per named model, the maker's links whose meshes get at least this many capsules (urdf_body's ``pieces``): the
#: Franka wrist's link 5 (an L-shaped casting) and link 7 (the flange's housing) pass close to each other, and with one
#: capsule each they overlapped in 32.6 % (Panda) and 25.6 % (FR3) of random configurations where the meshes meet in
#: 7.4 % and 0.9 %; with two and three, 17 % and 3.9 %.
PIECES = {
    "franka-panda": {"fer_link5": 2, "fer_link7": 3},
    "franka-fr3": {"fr3_link5": 2, "fr3_link7": 3},
}
#: Per named model whose maker's description has macros only: the file that calls them (SOURCES names it), written
#: into a folder of its own.
CALLERS = {
    "barrett-wam7": """<?xml version="1.0"?>
<robot name="wam7" xmlns:xacro="http://ros.org/wiki/xacro">
  <xacro:include filename="$(find barrett_model)/models/arm.urdf.xacro"/>
  <link name="world"/>
  <xacro:wam_7dof prefix="wam" parent_link="world" xyz="0 0 0" rpy="0 0 0"/>
</robot>
""",
    "ufactory-xarm7": """<?xml version="1.0"?>
<robot name="xarm7" xmlns:xacro="http://ros.org/wiki/xacro">
  <xacro:include filename="$(find xarm_description)/urdf/xarm7/xarm7.urdf.xacro"/>
  <xacro:xarm7_urdf prefix=""/>
</robot>
""",
}


def constant_transforms(maker: redkin.SerialChain, named: redkin.SerialChain,
                        rng: np.random.Generator) -> tuple[np.ndarray, float]:
    """Per frame k, the transform T_k with B named.frames(q)[k] = maker.frames(q)[k] @ T_k for every q, and how far
    from constant it is over random q (the named model's lengths rounded as its source prints them).

    ``B`` places the named model's base in the maker's: the identity where the two bases coincide, else the
    constant ``maker.fk(q) named.fk(q)^-1`` where the two tips coincide (the WAM's named model has its base at the
    shoulder, the maker's description 0.346 m lower, on the floor)."""
    samples = _within_limits(named, rng, 8)
    spreads = []
    for base in (np.eye(4), maker.fk(samples[0]) @ np.linalg.inv(named.fk(samples[0]))):
        transforms = np.array([[np.linalg.inv(a) @ base @ b for a, b in zip(maker.frames(q), named.frames(q))]
                               for q in samples])
        spreads.append(float(np.max(np.abs(transforms - transforms[0]))))
        if spreads[-1] <= SPREAD:
            return transforms[0], spreads[-1]
    raise SystemExit(f"{named.name}: the maker's frames and the named model's differ by {min(spreads):.3g}: not the "
                     "same joint conventions")


def _within_limits(chain: redkin.SerialChain, rng: np.random.Generator, count: int) -> np.ndarray:
    """Random configurations within the limits (a joint without limits: within a turn)."""
    return rng.uniform(np.maximum(chain.lower, -np.pi), np.minimum(chain.upper, np.pi), (count, chain.n))


def body_yaml(model: str, folder: Path) -> str:
    """The body file of one named model (module docstring)."""
    name, xacro_args, base, tip, source = SOURCES[model]
    with tempfile.TemporaryDirectory() as own:
        path = folder / name
        if model in CALLERS:
            path = Path(own) / name
            path.write_text(CALLERS[model])
        return _body_yaml(model, path, folder, xacro_args, base, tip, source)


def _body_yaml(model: str, path: Path, folder: Path, xacro_args: dict, base: str | None, tip: str | None,
               source: str) -> str:
    named = redkin.get_robot(model)
    maker, body = urdf_body(path, base, tip, xacro_args=xacro_args, package_paths=[folder],
                            pieces=PIECES.get(model))
    if maker.n != named.n:
        raise SystemExit(f"{model}: the maker's chain has {maker.n} joints, the named model {named.n}")
    transforms, spread = constant_transforms(maker, named, np.random.default_rng(0))
    capsules: dict[str, list] = {}
    for frame, a, b, radius in zip(body.frame, body.a, body.b, body.radius):
        inverse = np.linalg.inv(transforms[frame])
        ends = [inverse[:3, :3] @ end + inverse[:3, 3] for end in (a, b)]
        capsules.setdefault(f"link_{frame}", []).append(
            {"a": [round(float(v), 6) + 0.0 for v in ends[0]], "b": [round(float(v), 6) + 0.0 for v in ends[1]],
             "radius": round(float(radius) + 1e-6, 6)})  # rounded outward: the capsule still contains the mesh
    data = {"capsules": capsules}
    numbered = body_data(data, named, numbered_link_frames(named))
    q = _within_limits(named, np.random.default_rng(1), SAMPLES)
    apart, pairs = pair_table(named, numbered, scene_of({"obstacles": []}), q)
    meshes = _frame_meshes(path, base, tip, xacro_args, folder)
    capsule_share, mesh_share = {}, {}
    link_pairs = [tuple(sorted(names)) for names in pairs.names]  # a link of several capsules: several entries
    for pair in dict.fromkeys(link_pairs):
        first, second = (int(name.split("_")[1]) for name in pair)
        columns = [k for k, other in enumerate(link_pairs) if other == pair]
        capsule_share[pair] = float(np.mean(np.any(apart[:, columns] < 0.0, axis=1)))
        mesh_share[pair] = _mesh_collisions(maker, meshes[first], meshes[second], first, second, q)
    never = sorted(pair for pair, share in mesh_share.items() if share == 0.0)
    always = sorted(pair for pair, share in mesh_share.items() if share == 1.0)
    unresolved = sorted(pair for pair, share in capsule_share.items()
                        if share == 1.0 and pair not in never + always)
    data["ignore"] = [list(pair) for pair in never + always + unresolved]
    reach = max(float(note.split("reaching up to ")[1].split(" m")[0]) for note in body.notes if "reaching" in note)
    data["notes"] = [f"built-in body of {model}: capsules fitted by redkin to the collision meshes of {source}, "
                     f"reaching up to {reach:.3g} m beyond them; link pairs whose meshes never or always meet in "
                     f"{SAMPLES} random configurations are not checked, as MoveIt's setup assistant disables them"]
    data["notes"] += [f"{a} and {b} are not checked: their capsules overlap in every one of {SAMPLES} random "
                      f"configurations, their meshes meet in {100 * mesh_share[(a, b)]:.2f} % of them; a body file "
                      "with finer shapes for these links can check them" for a, b in unresolved]
    checked = [pair for pair in capsule_share if pair not in never + always + unresolved]
    worst = max(checked, key=lambda pair: capsule_share[pair] - mesh_share[pair], default=None)
    if worst is not None and capsule_share[worst] - mesh_share[worst] > WORTH_SAYING:
        data["notes"].append(f"the capsules of {worst[0]} and {worst[1]} overlap in {100 * capsule_share[worst]:.1f} "
                             f"% of random configurations, their meshes in {100 * mesh_share[worst]:.1f} %: where "
                             "that pair blocks, a body file with finer shapes for them may free it")
    header = [f"# Built-in body of {model}, written by tools/builtin_bodies.py from {source}.",
              f"# The maker's link frames agree with this model's to {spread:.1g} (4x4 entries, metres) at random "
              "joint values.",
              "# Per mesh (the maker's link frames, carried into this model's frames link_0 .. link_7):"]
    header += [f"#   {_found_in(note, folder)}" for note in body.notes]
    header += [f"# Per link pair (beside the adjacent ones), the share of {SAMPLES} random configurations within the "
               "limits in which the meshes meet (coal) and the capsules overlap:"]
    header += [f"#   {a} - {b}: meshes {100 * mesh_share[(a, b)]:.2f} %, capsules {100 * share:.2f} %"
               + ("  (ignored: the meshes never meet)" if (a, b) in never else
                  "  (ignored: the meshes always meet)" if (a, b) in always else
                  "  (ignored: the capsules always overlap)" if (a, b) in unresolved else "")
               for (a, b), share in sorted(capsule_share.items())]
    return "\n".join(header) + "\n" + yaml.safe_dump(data, sort_keys=False, width=120, default_flow_style=None)


def _found_in(note: str, folder: Path) -> str:
    """A note with this machine's path to a package below MAKERS_FOLDER written as ``$(find PKG)``."""
    return re.sub(re.escape(str(folder.resolve())) + r"/([^/]+)", r"$(find \1)", note)


def _frame_meshes(path: Path, base: str | None, tip: str | None, xacro_args: dict,
                  folder: Path) -> dict[int, list]:
    """Per chain frame of the maker's URDF, its collision meshes as coal BVH models in that frame's coordinates."""
    import coal
    from urdf_parser_py.urdf import Mesh

    from redkin.collision.link_frames import _urdf_links
    from redkin.collision.mesh_files import mesh_path, read_mesh
    from redkin.urdf import _origin

    _, robot, links = _urdf_links(path, base, tip, xacro_args, [folder])
    meshes: dict[int, list] = {}
    for link in robot.links:
        if link.name not in links:
            continue
        frame, pose = links[link.name]
        for collision in link.collisions:
            if not isinstance(collision.geometry, Mesh):
                raise SystemExit(f"{path}: link {link.name} has a collision that is not a mesh")
            vertices, faces = read_mesh(mesh_path(collision.geometry.filename, path, [folder]),
                                        collision.geometry.scale)
            place = pose @ _origin(collision)
            vertices = vertices @ place[:3, :3].T + place[:3, 3]
            model = coal.BVHModelOBBRSS()
            model.beginModel(len(faces), len(vertices))
            for triangle in faces:
                model.addTriangle(*(np.array(vertices[i], dtype=float) for i in triangle))
            model.endModel()
            meshes.setdefault(frame, []).append(model)
    return meshes


def _mesh_collisions(chain: redkin.SerialChain, first: list, second: list, i: int, j: int, q: np.ndarray) -> float:
    """The share of the configurations ``q`` at which a mesh of frame ``i`` meets one of frame ``j`` (coal)."""
    import coal

    frames = chain.frames(q)
    hits = 0
    for at in frames:
        place_i = coal.Transform3s(at[i][:3, :3].copy(), at[i][:3, 3].copy())
        place_j = coal.Transform3s(at[j][:3, :3].copy(), at[j][:3, 3].copy())
        hits += any(coal.collide(a, place_i, b, place_j, coal.CollisionRequest(), coal.CollisionResult())
                    for a in first for b in second)
    return hits / len(q)


def main() -> None:
    folder = Path(sys.argv[1])
    out = Path(__file__).resolve().parents[1] / "src" / "redkin" / "collision" / "bodies"
    out.mkdir(exist_ok=True)
    for model in sys.argv[2:] or SOURCES:
        (out / f"{model}.yaml").write_text(body_yaml(model, folder))
        print(f"wrote {out / (model + '.yaml')}")


if __name__ == "__main__":
    main()
