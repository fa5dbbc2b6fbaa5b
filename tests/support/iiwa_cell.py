"""The iiwa14 body and joint path the path-in-a-cell tests share: three capsules (upper arm, forearm, hand) in the
iiwa14's DH frames, and two configurations whose joint-space line gives the waypoints' poses."""

from __future__ import annotations

from redkin.chain import SerialChain
from redkin.collision import Body, BodyCapsule, body_of

#: The configurations at the two ends of the tests' joint-space line (radians).
START = [0.3, 0.6, -0.2, -1.2, 0.4, 0.8, 0.1]
END = [-0.5, 0.9, 0.4, -0.7, -0.3, -0.6, 0.9]


#: Capsules on frames 3 (upper arm), 4 (forearm) and 7 (hand) of an iiwa14-like chain.
CAPSULES = (BodyCapsule("upper arm", 3, [0, 0, -0.2], [0, 0, 0], 0.05),
            BodyCapsule("forearm", 4, [0, 0, 0], [0, 0.2, 0], 0.05),
            BodyCapsule("hand", 7, [0, 0, 0], [0, 0, 0.08], 0.04))


def three_capsules(chain: SerialChain) -> Body:
    """The body of :data:`CAPSULES` on ``chain``."""
    return body_of(list(CAPSULES), chain)
