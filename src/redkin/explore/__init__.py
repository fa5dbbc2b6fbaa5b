"""An interactive explorer of one pose's redundancy: one self-contained HTML page per arm and pose.

* :func:`explorer_data` -- every number the page shows, for all eight branches, over the arm's redundancy
  parameter (the arm angle psi of S-R-S, offset-elbow and nearly S-R-S arms, q7 of the Franka class): a dense grid
  with the exact ends of the feasible sets, the singular (psi) and optimal values merged in, joint values and
  postures, computed with the public :mod:`redkin.srs` or :mod:`redkin.franka` functions
* :func:`explorer_html` -- the page: a slider over the parameter, the joint curves with limits and sets, the
  posture in 3-D, a branch selector and the joint values; it works offline, from a file; it reads the parameter's
  name, domain and marks from the data and never asks which class it holds

``redkin explore ROBOT --position X Y Z --rotation R... --out FILE.html`` writes one.
"""

from redkin.explore.curves import BranchCurves, ExplorerData, Mark, Parameter
from redkin.explore.data import GRID_SAMPLES, explorer_data
from redkin.explore.page import explorer_html

__all__ = ["GRID_SAMPLES", "BranchCurves", "ExplorerData", "Mark", "Parameter", "explorer_data", "explorer_html"]
