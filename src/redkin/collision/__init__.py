"""Obstacles and the arm's body (issue 40), first steps: the shapes of a cell as rows one compiled kernel reads
(:mod:`redkin.collision.primitives`), a cell's scene file (:func:`read_scene`, :class:`Scene`).

* :func:`read_scene` -- the obstacles of a YAML or JSON scene file in the arm's base frame (boxes, capsules,
  spheres, planes) and the margin to keep from them; :func:`scene_of` the same from data already read
* :func:`sphere`, :func:`capsule`, :func:`box`, :func:`plane` -- one shape as a row of :data:`WIDTH` numbers
"""

from redkin.collision.primitives import BOX, CAPSULE, PLANE, SPHERE, WIDTH, box, capsule, plane, sphere
from redkin.collision.scene import Scene, read_scene, scene_of

__all__ = ["BOX", "CAPSULE", "PLANE", "SPHERE", "WIDTH", "Scene", "box", "capsule", "plane", "read_scene", "scene_of",
           "sphere"]
