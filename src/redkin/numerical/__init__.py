"""Numerical pose IK for any serial chain within its joint limits, every solution certified by our FK.

See docs/numerical-ik.md: damped Gauss-Newton steps with the limits, restarts, and the certificate [N1]-[N5].
"""

from redkin.numerical.solve import NumericalSolutions, ik

__all__ = ["NumericalSolutions", "ik"]
