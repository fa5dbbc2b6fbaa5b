"""An interactive explorer of one pose's redundancy: one self-contained HTML page per arm and pose.

* :func:`explorer_data` -- every number the page shows, for all eight branches, over the arm's redundancy
  parameter (the arm angle psi of S-R-S, offset-elbow and nearly S-R-S arms, q7 of the Franka class): a dense grid
  with the exact ends of the feasible sets, the singular and optimal values merged in, joint values and
  postures, from what :meth:`redkin.arms.Arm.analyse` answers for every class
* :func:`explorer_html` -- the page: a slider over the parameter, the joint curves with limits and sets, the
  posture in 3-D, a branch selector and the joint values; it works offline, from a file; it reads the parameter's
  name, domain and marks from the data and never asks which class it holds

* :func:`playback_html` -- a timed path played back: the arm moving, a time slider, every joint's value and speed
  against its limits, the reconfiguration stops (:class:`StopSpan`) shaded; :data:`FRAME_RATE` frames per second of
  the trajectory's time, at most :data:`MAX_FRAMES`

``redkin explore ROBOT --position X Y Z --rotation R... --out FILE.html`` writes one; ``redkin explore ROBOT --path
RESULT.json`` and ``redkin path --playback`` write the playback page.
"""

from redkin.explore.curves import BranchCurves, ExplorerData, Mark
from redkin.explore.data import GRID_SAMPLES, explorer_data
from redkin.explore.page import explorer_html
from redkin.explore.playback import FRAME_RATE, MAX_FRAMES, StopSpan, playback_html

__all__ = ["GRID_SAMPLES", "BranchCurves", "ExplorerData", "Mark", "explorer_data", "explorer_html",
           "FRAME_RATE", "MAX_FRAMES", "StopSpan", "playback_html"]
