"""Obstacles and the arm's body (issue 40): the shapes of a cell as rows one compiled kernel reads
(:mod:`redkin.collision.primitives`), a cell's scene file (:func:`read_scene`, :class:`Scene`), the signed distances
between shapes (:func:`signed_distance`), the arm's body (:class:`Body`) and the certified collision-free arm angles
of S-R-S arms (:func:`collision_free_arm_angles`).

* :func:`read_scene` -- the obstacles of a YAML or JSON scene file in the arm's base frame (boxes, capsules,
  spheres, planes, meshes covered by boxes) and the margin to keep from them; :func:`scene_of` the same from data
  already read
* :func:`sphere`, :func:`capsule`, :func:`box`, :func:`plane` -- one shape as a row of :data:`WIDTH` numbers
* :func:`signed_distance` -- per pair of rows (batched, broadcast), the signed distance (negative: penetrating)
  and a witness point on each shape, for a sphere or capsule against any shape, compiled closed forms
* :func:`urdf_link_frames` -- a URDF's chain and where each of its links sits in the chain's frames
  (:class:`LinkFrame`); :func:`numbered_link_frames` the links ``link_0 .. link_n`` of a chain without link names
* :func:`read_body` -- the arm's body from a YAML or JSON body file of spheres and capsules per link, and the link
  pairs to skip; :func:`body_data` the same from data already read
* :func:`urdf_body` -- a URDF's chain and the body of its ``<collision>`` elements (spheres exact, cylinders, boxes
  and mesh files covered by capsules, each note saying by how much), with an SRDF's disabled pairs
  (:func:`srdf_ignored_pairs`)
* :func:`covering_capsules` -- one to three capsules that contain a mesh, and how far each reaches beyond it
  (:class:`MeshCapsule`; the ``mesh`` extra); :func:`covering_boxes` the same with oriented boxes (:class:`MeshBox`),
  which a scene's mesh obstacles become
* :func:`builtin_body` -- a named model's built-in body, capsules fitted to its maker's collision meshes
  (:func:`builtin_models` lists the models that have one)
* :func:`body_of` -- a body from capsules fixed in the chain's frames (:class:`BodyCapsule`), with its
  self-collision pairs; :func:`posed` its capsules in the base frame at given frames
* :func:`clearance` -- at joint values of any arm, the least distance between the body and the obstacles or itself,
  and the pair that has it (:class:`Clearance`)
* :func:`step_clearance` -- whether each step between configurations (the joints moving linearly) keeps the
  margin, proved by a bound on how far the body can move (:class:`StepClearance`); :func:`steps_between` the same
  of steps given by their two ends
* :func:`collision_free_ik` -- on any arm, the numerical solver's certified solutions of a pose that keep the margin,
  and the candidates refused (:class:`FreeSolutions`)
* :func:`collision_free_arm_angles` -- per branch of one pose, the certified arm angles within the limits and clear of
  every obstacle and of the body itself by the margin, and each removed stretch's cause (:class:`FreeArmAngles`,
  :class:`Stretch`); :func:`free_arm_angles_of` the same of many poses, decided together
* :func:`collision_free_q7` -- the same on Franka-class arms, over q7 (:func:`free_q7_of` for many poses)
* :func:`collision_free_set` -- whichever of the two the arm's class has (:func:`free_sets_of` for many poses)
"""

from redkin.collision.arm_angle_free import FreeArmAngles, Stretch, collision_free_arm_angles, free_arm_angles_of
from redkin.collision.body import Body, BodyCapsule, body_of, posed
from redkin.collision.body_file import body_data, read_body
from redkin.collision.builtin import builtin_body, builtin_models
from redkin.collision.clearance import Clearance, clearance
from redkin.collision.distances import Distance, signed_distance
from redkin.collision.free_ik import FreeSolutions, collision_free_ik
from redkin.collision.free_sets import collision_free_set, free_sets_of
from redkin.collision.link_frames import LinkFrame, numbered_link_frames, urdf_link_frames
from redkin.collision.mesh_cover import MeshBox, MeshCapsule, covering_boxes, covering_capsules
from redkin.collision.primitives import BOX, CAPSULE, PLANE, SPHERE, WIDTH, box, capsule, plane, sphere
from redkin.collision.q7_free import collision_free_q7, free_q7_of
from redkin.collision.scene import Scene, read_scene, scene_of
from redkin.collision.steps import StepClearance, step_clearance, steps_between
from redkin.collision.urdf_body import srdf_ignored_pairs, urdf_body

__all__ = ["BOX", "CAPSULE", "PLANE", "SPHERE", "WIDTH", "Distance", "Scene", "box", "capsule", "plane", "read_scene",
           "scene_of", "signed_distance", "sphere", "LinkFrame", "urdf_link_frames", "numbered_link_frames",
           "read_body", "body_data", "urdf_body", "srdf_ignored_pairs", "Body", "BodyCapsule", "body_of", "posed",
           "FreeArmAngles", "Stretch", "collision_free_arm_angles", "free_arm_angles_of", "collision_free_q7",
           "free_q7_of", "collision_free_set", "free_sets_of", "FreeSolutions",
           "collision_free_ik", "Clearance", "clearance", "StepClearance", "step_clearance", "steps_between",
           "MeshCapsule", "covering_capsules", "MeshBox", "covering_boxes", "builtin_body", "builtin_models"]
