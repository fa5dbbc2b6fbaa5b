"""MJCF import: the serial chain between two bodies of a MuJoCo model, as exact DH rows.

The file is compiled by MuJoCo itself (the ``mujoco`` package, the optional
extra ``mjcf``: ``pip install "redkin[mjcf]"``, or ``pip install -e ".[mjcf]"``
in a checkout): ``<default>`` classes, ``childclass``, ``<include>``, every
frame form (``quat``, ``axisangle``, ``euler`` with ``eulerseq``,
``xyaxes``, ``zaxis``), ``<compiler angle="degree">`` and the rest of MJCF
reach redkin as MuJoCo reads them, and nothing of MJCF is re-implemented here.

Joint values.  A hinge's ``qpos`` is its MuJoCo joint value, and redkin's
``q`` for that joint is the same number: ``q = 0`` is ``qpos = 0``.  MuJoCo
turns a hinge by ``qpos - ref`` from the pose the file writes (``ref``
defaults to 0, so most files need no thought); with a ``ref`` the written pose
is ``q = ref``.  The ranges are the compiled ``jnt_range``, on ``qpos``, in
radians whatever ``<compiler angle>`` said; an unlimited hinge gets
``-inf``/``inf``.  MJCF gives a joint no speed limit (an actuator's
``ctrlrange`` bounds its control, whatever that drives), so the chain's
``velocity`` is unknown on every joint (:meth:`SerialChain.with_velocity`
sets it).

Conversion.  With every joint's ``qpos`` at its ``qpos0`` and the chain's
hinges at 0, ``mj_kinematics`` gives each hinge's world anchor
(``data.xanchor``) and axis (``data.xaxis``), the base body's pose and the
tip's (a body's ``xpos``/``xmat``, or a site's).  Expressed in the base body's
frame, the anchors and axes are the joint lines of
:func:`redkin._joint_lines.dh_rows_from_lines`, exactly as :mod:`redkin.urdf`
uses them: ``base @ A_1 ... A_n @ tool`` is the tip's pose in the base body's
frame for every ``q``.  A body with several hinges turns by them in the order
written, the first nearest the base, as MuJoCo composes them; each becomes
one row.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from redkin._extras import missing_extra
from redkin._joint_lines import dh_rows_from_lines
from redkin.chain import SerialChain
from redkin.errors import RedkinError, RobotDescriptionError
from redkin.examples import resolve

#: The mass [kg] and inertia given to a body without one, so that a kinematics-only file compiles.
_LEAST_MASS = 1e-6
#: MuJoCo's name for a model whose ``<mujoco>`` element has no ``model`` attribute.
_UNNAMED_MODEL = "MuJoCo Model"


def load_mjcf(path: str | Path, base: str | None = None, tip: str | None = None) -> SerialChain:
    """The chain from body ``base`` to body or site ``tip`` of the MJCF file at ``path``.

    Parameters
    ----------
    path : str or Path
        An MJCF (MuJoCo XML) file; the files it includes and its assets
        (meshes) are found as MuJoCo finds them, relative to it.  A path
        that does not exist may name a shipped example
        (:func:`redkin.examples.resolve`: ``examples/iiwa14.xml``).
    base : str, optional
        A body name; default ``"world"``, MuJoCo's world frame, so that poses
        are those MuJoCo reports (``data.xpos``).
    tip : str, optional
        A body name or, where no body has that name, a site name; default the
        one leaf body below ``base`` (a tree with several leaves must name it).

    Returns
    -------
    SerialChain
        Standard DH rows (see the module docstring), named after the model,
        with the hinges' names and compiled ranges; ``q`` is MuJoCo's ``qpos``.

    Raises
    ------
    RobotDescriptionError
        For a missing or malformed file (MuJoCo's whole reason, in one line),
        an unknown body or site (the names are listed), a tip not below the
        base, a tree without a single leaf, and a slide, ball or free joint or
        a joint coupled by an ``<equality><joint>`` on the way (named); its
        ``path`` and ``key`` (the body, site or joint) say where.
    RedkinError
        When the ``mjcf`` extra (the ``mujoco`` package) is not installed.
    """
    path = resolve(path)
    mujoco, model = _compile(path)
    where = str(path)
    base_id = 0 if base is None else _body_id(mujoco, model, base, "base", where)
    if tip is None:
        tip_body, tip_site = _only_leaf(mujoco, model, base_id, where), -1
    else:
        tip_body = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, tip))
        tip_site = -1 if tip_body >= 0 else int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, tip))
        if tip_body < 0 and tip_site < 0:
            raise RobotDescriptionError(
                f"{where}: no body or site named {tip!r} for the tip (bodies: {_names(model.body, model.nbody)}; "
                f"sites: {_names(model.site, model.nsite)})", path=where, key=tip)
        if tip_site >= 0:
            tip_body = int(model.site_bodyid[tip_site])
    base_name, tip_name = _label(model.body, base_id), tip if tip is not None else _label(model.body, tip_body)
    joints = _hinges(mujoco, model, _bodies_between(model, base_id, tip_body, tip_name, where), where)
    if not joints:
        raise RobotDescriptionError(f"{where}: no hinge joint between body {base_name!r} and {tip_name!r}",
                                    path=where, key=tip_name)

    data = mujoco.MjData(model)
    data.qpos[:] = model.qpos0
    data.qpos[model.jnt_qposadr[joints]] = 0.0  # q = 0 is qpos = 0 on the chain (see the module docstring)
    mujoco.mj_kinematics(model, data)
    frame = _pose(data.xpos[base_id], data.xmat[base_id])
    end = _pose(data.site_xpos[tip_site], data.site_xmat[tip_site]) if tip_site >= 0 else \
        _pose(data.xpos[tip_body], data.xmat[tip_body])
    to_base = np.linalg.inv(frame)
    points = (data.xanchor[joints] - frame[:3, 3]) @ frame[:3, :3]  # R^T (p - o) for each row p
    directions = data.xaxis[joints] @ frame[:3, :3]
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)

    limited = model.jnt_limited[joints].astype(bool)
    lower = np.where(limited, model.jnt_range[joints, 0], -np.inf)
    upper = np.where(limited, model.jnt_range[joints, 1], np.inf)
    rows, first, last = dh_rows_from_lines(points, directions)
    model_name = model.names[: model.names.index(b"\0")].decode()
    kind = "site" if tip_site >= 0 else "body"
    return SerialChain(
        a=rows[:, 0], alpha=rows[:, 1], d=rows[:, 2], offset=rows[:, 3], convention="dh",
        lower=lower, upper=upper, base=first, tool=np.linalg.inv(last) @ to_base @ end,
        name=model_name if model_name and model_name != _UNNAMED_MODEL else path.stem,
        source=f"MJCF {where}, body {base_name} -> {kind} {tip_name}",
        joint_names=[_joint_name(model, j) for j in joints],
    )


def _compile(path: Path):
    """The ``mujoco`` module and the compiled model of the file."""
    try:
        import mujoco
    except ImportError:
        raise RedkinError(missing_extra("reading an MJCF file needs mujoco", "mjcf")) from None
    try:
        path.open("rb").close()
    except OSError as exc:
        raise RobotDescriptionError(f"cannot read robot file {str(path)!r}: {exc.strerror or exc}",
                                    path=str(path)) from None
    try:
        spec = mujoco.MjSpec.from_file(str(path))
        # a kinematic description (bodies and joints, no geoms or inertials) is complete for a chain: give massless
        # bodies a least mass instead of refusing them (larger masses are untouched; no mass enters the chain)
        spec.compiler.boundmass = max(spec.compiler.boundmass, _LEAST_MASS)
        spec.compiler.boundinertia = max(spec.compiler.boundinertia, _LEAST_MASS)
        return mujoco, spec.compile()
    except Exception as exc:  # the compiler raises ValueError with its message; anything else is as malformed
        lines = [line.strip() for line in str(exc).splitlines() if line.strip()]
        reason = "; ".join(lines) if lines else type(exc).__name__
        raise RobotDescriptionError(f"{path}: malformed MJCF: {reason}", path=str(path)) from None


def _label(views, index: int) -> str:
    """An element's name, or MuJoCo's id for an unnamed one."""
    name = views(index).name
    return name if name else f"#{index}"


def _names(views, count: int) -> str:
    names = [views(i).name for i in range(count) if views(i).name]
    return ", ".join(sorted(names)) if names else "none named"


def _body_id(mujoco, model, name: str, role: str, where: str) -> int:
    index = int(mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_BODY, name))
    if index < 0:
        site = " (a site: the base must be a body)" if mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, name) >= 0 \
            else ""
        raise RobotDescriptionError(f"{where}: no body named {name!r} for the {role}{site} "
                                    f"(bodies: {_names(model.body, model.nbody)})", path=where, key=name)
    return index


def _only_leaf(mujoco, model, base: int, where: str) -> int:
    """The one body below ``base`` without child bodies."""
    children: dict[int, list[int]] = {}
    for body in range(1, model.nbody):
        children.setdefault(int(model.body_parentid[body]), []).append(body)
    leaves, stack = [], [base]
    while stack:
        body = stack.pop()
        below = children.get(body, [])
        if not below:
            leaves.append(body)
        stack.extend(below)
    if len(leaves) != 1:
        names = ", ".join(sorted(_label(model.body, b) for b in leaves))
        base_name = _label(model.body, base)
        raise RobotDescriptionError(f"{where}: the tree below body {base_name!r} has {len(leaves)} leaves "
                                    f"({names}); name one with --tip", path=where, key=base_name)
    return leaves[0]


def _bodies_between(model, base: int, tip: int, tip_name: str, where: str) -> list[int]:
    """The bodies below ``base`` down to ``tip`` (inclusive), base side first."""
    bodies = []
    body = tip
    while body != base:
        if body == 0:
            raise RobotDescriptionError(f"{where}: {tip_name!r} is not below body {_label(model.body, base)!r}",
                                        path=where, key=tip_name)
        bodies.append(body)
        body = int(model.body_parentid[body])
    return bodies[::-1]


def _hinges(mujoco, model, bodies: list[int], where: str) -> list[int]:
    """The joints of ``bodies`` in MuJoCo's order, all of them hinges and none coupled to another joint."""
    joints = []
    for body in bodies:
        start, count = int(model.body_jntadr[body]), int(model.body_jntnum[body])
        for joint in range(start, start + count):
            kind = mujoco.mjtJoint(int(model.jnt_type[joint]))
            if kind != mujoco.mjtJoint.mjJNT_HINGE:
                raise RobotDescriptionError(
                    f"joint {_joint_name(model, joint)!r} of body {_label(model.body, body)!r} is a "
                    f"{kind.name.removeprefix('mjJNT_').lower()} joint: redkin chains have hinge joints only",
                    path=where, key=_joint_name(model, joint))
            joints.append(joint)
    coupled = {int(model.eq_obj1id[e]): int(model.eq_obj2id[e]) for e in range(model.neq)
               if int(model.eq_type[e]) == mujoco.mjtEq.mjEQ_JOINT}
    coupled |= {other: joint for joint, other in coupled.items() if other >= 0}
    for joint in joints:
        if joint in coupled:
            other = coupled[joint]
            partner = f" to joint {_joint_name(model, other)!r}" if other >= 0 else " to a constant"
            raise RobotDescriptionError(f"joint {_joint_name(model, joint)!r} is coupled{partner} by an "
                                        "<equality><joint>: coupled joints are not supported", path=where,
                                        key=_joint_name(model, joint))
    return joints


def _joint_name(model, joint: int) -> str:
    """The joint's name; an unnamed one is called after its body (and its place there if the body has several)."""
    name = model.joint(joint).name
    if name:
        return name
    body = int(model.jnt_bodyid[joint])
    place = joint - int(model.body_jntadr[body])
    return f"{_label(model.body, body)} joint" + (f" {place + 1}" if int(model.body_jntnum[body]) > 1 else "")


def _pose(position: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    pose = np.eye(4)
    pose[:3, :3] = np.asarray(matrix).reshape(3, 3)
    pose[:3, 3] = position
    return pose
