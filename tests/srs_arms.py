"""Arms for the arm-angle tests: the named models, and random S-R-S and offset-elbow arms."""

import numpy as np

from redkin.chain import SerialChain
from redkin.models import barrett_wam, kuka_iiwa14, pa10_7c, srs_chain
from redkin.srs.geometry import TABLE1_ALPHA

#: ``pa10``, ``iiwa``, ``wam``: the models; ``srs``: random S-R-S lengths; ``offset``: a random offset elbow.
ARM_KINDS = ("pa10", "iiwa", "wam", "srs", "offset")


def offset_elbow_chain(d_bs: float, d_se: float, d_ew: float, d_wt: float, a3: float, a4: float) -> SerialChain:
    """Paper 000 Table 1 with elbow offsets ``a_3``, ``a_4`` (the WAM has 0.045 and -0.045 m)."""
    return SerialChain(a=[0.0, 0.0, a3, a4, 0.0, 0.0, 0.0], alpha=TABLE1_ALPHA,
                       d=[d_bs, 0.0, d_se, 0.0, d_ew, 0.0, d_wt], name="offset-elbow")


def arm(kind: str, rng: np.random.Generator) -> SerialChain:
    """A chain of one of :data:`ARM_KINDS` (random lengths drawn from ``rng``)."""
    if kind == "srs":
        return srs_chain(*rng.uniform(0.1, 0.8, 4))
    if kind == "offset":
        return offset_elbow_chain(*rng.uniform(0.05, 0.8, 4), *rng.uniform(-0.15, 0.15, 2))
    return {"pa10": pa10_7c, "iiwa": kuka_iiwa14, "wam": barrett_wam}[kind]()
