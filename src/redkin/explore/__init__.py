"""An interactive arm-angle explorer: one self-contained HTML page per arm and pose.

* :func:`explorer_data` -- every number the page shows, for all eight branches
  (a dense arm-angle grid with the exact ends of the feasible sets, the
  singular and optimal arm angles, joint values and postures), computed with
  the public :mod:`redkin.srs` functions
* :func:`explorer_html` -- the page: a slider over the arm angle, the joint
  curves with limits and sets, the posture in 3-D, a branch selector and
  the joint values; it works offline, from a file

``redkin explore ROBOT --position X Y Z --rotation R... --out FILE.html`` writes one.
"""

from redkin.explore.data import GRID_SAMPLES, BranchCurves, ExplorerData, Mark, explorer_data
from redkin.explore.page import explorer_html

__all__ = ["GRID_SAMPLES", "BranchCurves", "ExplorerData", "Mark", "explorer_data", "explorer_html"]
