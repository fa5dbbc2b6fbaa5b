"""Obstacles and the arm's body (issue 40), first steps: the shapes of a cell as rows one compiled kernel reads
(:mod:`redkin.collision.primitives`), a cell's scene file (:func:`read_scene`, :class:`Scene`) and the signed
distances between shapes (:func:`signed_distance`).

* :func:`read_scene` -- the obstacles of a YAML or JSON scene file in the arm's base frame (boxes, capsules,
  spheres, planes) and the margin to keep from them; :func:`scene_of` the same from data already read
* :func:`sphere`, :func:`capsule`, :func:`box`, :func:`plane` -- one shape as a row of :data:`WIDTH` numbers
* :func:`signed_distance` -- per pair of rows (batched, broadcast), the signed distance (negative: penetrating)
  and a witness point on each shape, for a sphere or capsule against any shape, compiled closed forms
"""

from redkin.collision.distances import Distance, signed_distance
from redkin.collision.primitives import BOX, CAPSULE, PLANE, SPHERE, WIDTH, box, capsule, plane, sphere
from redkin.collision.scene import Scene, read_scene, scene_of

__all__ = ["BOX", "CAPSULE", "PLANE", "SPHERE", "WIDTH", "Distance", "Scene", "box", "capsule", "plane", "read_scene",
           "scene_of", "signed_distance", "sphere"]
