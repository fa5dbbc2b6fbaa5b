"""The URDF definition itself as a reference, without redkin: the tip pose of a URDF and synthetic single-chain URDFs.

``reference_fk`` reads the XML with ``xml.etree`` (not the parser redkin uses) and multiplies the
joints' ``<origin>`` transforms and Rodrigues rotations about their ``<axis>``, as the URDF
specification defines the tip pose.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np


# ----------------------------------------------------------------------------- the reference
def _rotation(rpy) -> np.ndarray:
    r, p, y = rpy
    rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
    ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
    return rz @ ry @ rx


def axis_angle(axis, angle) -> np.ndarray:
    """Rodrigues: the rotation by ``angle`` about ``axis``."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    skew = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(angle) * skew + (1 - np.cos(angle)) * skew @ skew


def _joints_to(text: str, tip: str) -> list:
    """The ``<joint>`` elements from the root link down to ``tip``, in order."""
    root = ET.fromstring(text)
    by_child = {j.find("child").get("link"): j for j in root.findall("joint")}
    path, link = [], tip
    while link in by_child:
        path.append(by_child[link])
        link = by_child[link].find("parent").get("link")
    return path[::-1]


def reference_fk(text: str, q: np.ndarray, tip: str) -> np.ndarray:
    """The tip link's pose in the root link's frame, straight from the URDF definition."""
    pose, k = np.eye(4), 0
    for joint in _joints_to(text, tip):
        origin = joint.find("origin")
        step = np.eye(4)
        if origin is not None:
            step[:3, :3] = _rotation([float(v) for v in origin.get("rpy", "0 0 0").split()])
            step[:3, 3] = [float(v) for v in origin.get("xyz", "0 0 0").split()]
        pose = pose @ step
        if joint.get("type") in ("revolute", "continuous"):
            turn = np.eye(4)
            turn[:3, :3] = axis_angle([float(v) for v in joint.find("axis").get("xyz").split()], q[k])
            pose, k = pose @ turn, k + 1
    return pose


def reference_axes(text: str, tip: str) -> np.ndarray:
    """World directions ``(n, 3)`` at q = 0 of the moving joints' axes on the way to ``tip``, from the URDF itself."""
    rotation, axes = np.eye(3), []
    for joint in _joints_to(text, tip):
        origin = joint.find("origin")
        if origin is not None:
            rotation = rotation @ _rotation([float(v) for v in origin.get("rpy", "0 0 0").split()])
        if joint.get("type") in ("revolute", "continuous"):
            axis = np.array([float(v) for v in joint.find("axis").get("xyz").split()])
            axes.append(rotation @ (axis / np.linalg.norm(axis)))
    return np.array(axes)


# ----------------------------------------------------------------------------- synthetic URDFs
def urdf(joints: list[tuple], name: str = "synthetic") -> str:
    """``joints``: (type, xyz, rpy, axis) from the root link down a single chain."""
    links = "".join(f'<link name="l{k}"/>' for k in range(len(joints) + 1))
    body = ""
    for k, (kind, xyz, rpy, axis) in enumerate(joints):
        limit = '<limit lower="-2" upper="2.5" effort="1" velocity="1"/>' if kind == "revolute" else ""
        axis_tag = f'<axis xyz="{axis}"/>' if kind != "fixed" else ""
        body += (f'<joint name="j{k}" type="{kind}"><parent link="l{k}"/><child link="l{k + 1}"/>'
                 f'<origin xyz="{xyz}" rpy="{rpy}"/>{axis_tag}{limit}</joint>')
    return f'<robot name="{name}">{links}{body}</robot>'
