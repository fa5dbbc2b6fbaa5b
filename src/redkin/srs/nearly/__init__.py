"""Nearly S-R-S arms (docs/srs.md, "Nearly S-R-S arms"): arm-angle IK on the real arm through its exact S-R-S
neighbour, certified, and what the exact classes know of the arm angle located on the real arm.

* :mod:`redkin.srs.nearly.arm` -- the neighbour (:func:`nearly_srs`), the real arm's arm angle and branch, and its
  certified solutions at an arm angle (:func:`ik`);
* :mod:`redkin.srs.nearly.bound` -- how far the neighbour's solution is from the real arm's;
* :mod:`redkin.srs.nearly.self_motion` -- the pose's self-motion, traced and certified;
* :mod:`redkin.srs.nearly.feasible`, :mod:`~redkin.srs.nearly.optimal`, :mod:`~redkin.srs.nearly.singular` -- the
  feasible, limit-avoiding and singular arm angles read off it;
* :mod:`redkin.srs.nearly.search` -- the polishing the last two share.

The compiled kernels are :mod:`redkin.srs.nearly._kernels` and :mod:`redkin.srs.nearly._self_motion_kernels`.
"""

from redkin.srs.nearly.arm import (
    TOLERANCE,
    TOLERANCE_DEFAULT,
    NearlySolutions,
    NearlySRS,
    arm_angle,
    branch_of,
    ik,
    ik_continued,
    nearly_srs,
    reach,
    self_motion_rates,
)

__all__ = ["TOLERANCE", "TOLERANCE_DEFAULT", "NearlySRS", "NearlySolutions", "arm_angle", "branch_of", "ik",
           "ik_continued", "nearly_srs", "reach", "self_motion_rates"]
