"""One arm, one API (:func:`arm`, :class:`Arm`): every class of arm asked the same questions, answered in the same
shapes (:class:`Solutions`, :class:`FeasibleSets`, :class:`Analysis`)."""

from redkin.arms.analysis import Analysis, BranchAnalysis, SingularPart
from redkin.arms.feasible_sets import Arcs, FeasibleSets
from redkin.arms.front_door import Arm, Optimal, Singular, arm
from redkin.arms.parameter import Parameter
from redkin.arms.solutions import Solutions

__all__ = ["Analysis", "Arcs", "Arm", "BranchAnalysis", "FeasibleSets", "Optimal", "Parameter", "Singular",
           "SingularPart", "Solutions", "arm"]
