"""Laws of the compiled chain kernels (redkin._chain_kernels) on random and degenerate chains.

The reference is the definition: a product of 4x4 DH matrices written here
from ``np.cos`` and ``np.sin``, independent of the kernels.
"""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from redkin import _chain_kernels, _compiled
from redkin._compiled import PARALLEL_BATCH, set_threads
from redkin.chain import SerialChain

QUARTER_TURNS = [0.0, np.pi / 2, -np.pi / 2, np.pi, -np.pi]
SPECIAL_ANGLES = [0.0, np.pi / 2, -np.pi / 2, np.pi, -np.pi, 2 * np.pi]


def rz(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]])


def rx(alpha):
    c, s = np.cos(alpha), np.sin(alpha)
    return np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])


def translation(x, y, z):
    out = np.eye(4)
    out[:3, 3] = x, y, z
    return out


def reference_frames(chain: SerialChain, q: np.ndarray) -> list[np.ndarray]:
    """base, base A_1, ..., base A_1 ... A_n, and that times the tool: the DH definitions multiplied out."""
    frames = [chain.base.copy()]
    for i in range(chain.n):
        theta = chain.offset[i] + chain.sign[i] * q[i]
        if chain.convention == "dh":
            link = rz(theta) @ translation(0, 0, chain.d[i]) @ translation(chain.a[i], 0, 0) @ rx(chain.alpha[i])
        else:
            link = rx(chain.alpha[i]) @ translation(chain.a[i], 0, 0) @ rz(theta) @ translation(0, 0, chain.d[i])
        frames.append(frames[-1] @ link)
    return frames + [frames[-1] @ chain.tool]


def rigid(angles, shift):
    """A rigid transform from three angles (Rz Rx Rz) and a translation."""
    return translation(*shift) @ rz(angles[0]) @ rx(angles[1]) @ rz(angles[2])


lengths = st.one_of(st.just(0.0), st.floats(-1.0, 1.0))
twists = st.one_of(st.sampled_from(QUARTER_TURNS), st.floats(-np.pi, np.pi))
angles = st.one_of(st.sampled_from(SPECIAL_ANGLES), st.floats(-2 * np.pi, 2 * np.pi))
transforms = st.one_of(
    st.just(np.eye(4)),
    st.builds(rigid, st.tuples(angles, angles, angles), st.tuples(lengths, lengths, lengths)),
)


@st.composite
def chains(draw, max_joints=8):
    n = draw(st.integers(1, max_joints))
    row = lambda values: draw(st.lists(values, min_size=n, max_size=n))  # noqa: E731
    return SerialChain(
        a=row(lengths), alpha=row(twists), d=row(lengths),
        convention=draw(st.sampled_from(["dh", "mdh"])),
        offset=row(st.one_of(st.just(0.0), st.floats(-np.pi, np.pi))),
        sign=row(st.sampled_from([1.0, -1.0])),
        base=draw(transforms), tool=draw(transforms),
    )


@st.composite
def chains_and_q(draw):
    chain = draw(chains())
    return chain, np.array(draw(st.lists(angles, min_size=chain.n, max_size=chain.n)))


@given(chains_and_q())
@settings(max_examples=200, deadline=None)
def test_fk_and_frames_equal_the_product_of_dh_matrices(case):
    chain, q = case
    expected = reference_frames(chain, q)
    frames = chain.frames(q)
    assert frames.shape == (chain.n + 2, 4, 4)
    np.testing.assert_allclose(frames, np.array(expected), rtol=0, atol=1e-12)
    np.testing.assert_allclose(chain.fk(q), expected[-1], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(chain.fk(q), frames[-1])


def finite_difference_jacobian(chain, q, frame, offset, h=1e-6):
    """Central differences of the point's position and of the frame's rotation (omega from dR R^T)."""
    index = chain.n + 1 if frame is None else frame

    def pose(values):
        f = chain.frames(values)[index]
        return f[:3, :3] @ offset + f[:3, 3], f[:3, :3]

    rotation = pose(q)[1]
    jac = np.zeros((6, chain.n))
    for i in range(chain.n):
        step = np.zeros(chain.n)
        step[i] = h
        (p_plus, r_plus), (p_minus, r_minus) = pose(q + step), pose(q - step)
        jac[:3, i] = (p_plus - p_minus) / (2 * h)
        omega = (r_plus - r_minus) / (2 * h) @ rotation.T
        jac[3:, i] = omega[2, 1], omega[0, 2], omega[1, 0]
    return jac


@given(chains_and_q(), st.data())
@settings(max_examples=100, deadline=None)
def test_jacobian_equals_finite_differences(case, data):
    chain, q = case
    frame = data.draw(st.one_of(st.none(), st.integers(0, chain.n)))
    offset = np.array(data.draw(st.tuples(lengths, lengths, lengths)))
    jac = chain.jacobian(q, frame=frame, offset=offset)
    np.testing.assert_allclose(jac, finite_difference_jacobian(chain, q, frame, offset), rtol=0, atol=1e-7)
    if frame is not None:
        assert np.all(jac[:, frame:] == 0.0)
    np.testing.assert_array_equal(chain.jacobian(q), chain.jacobian(q, frame=None, offset=np.zeros(3)))


@given(chains_and_q(), st.data())
@settings(max_examples=100, deadline=None)
def test_jacobian_from_the_sines_frames_one_left_is_jacobian_one(case, data):
    """The pose and the Jacobian of one q share one set of sines and cosines: the Jacobian from those frames_one
    leaves equals the one that takes its own, bit for bit, on every frame and point."""
    chain, q = case
    links, ends, standard = chain._links, chain._ends, chain._standard
    active = data.draw(st.integers(0, chain.n))
    tool = data.draw(st.booleans()) if active == chain.n else False
    offset = np.array(data.draw(st.tuples(lengths, lengths, lengths)))
    trig, own = np.empty((chain.n, 2)), np.empty((6, chain.n))
    _chain_kernels.jacobian_one(q, links, ends, standard, active, tool, offset, trig, own)
    trig[:] = np.nan  # whatever jacobian_one left: the sines and cosines below are frames_one's
    _chain_kernels.frames_one(q, links, ends, standard, trig, np.empty((1, 4, 4)))
    shared = np.full((6, chain.n), np.nan)
    _chain_kernels.jacobian_from_trig(links, ends, standard, active, tool, offset, trig, shared)
    np.testing.assert_array_equal(shared, own)
    np.testing.assert_allclose(own, finite_difference_jacobian(chain, q, active if not tool else None, offset),
                               rtol=0, atol=1e-7)


@given(chains(), st.integers(0, 2**32 - 1))
@settings(max_examples=30, deadline=None)
def test_batches_equal_single_calls(chain, seed):
    """A batch above PARALLEL_BATCH runs in chunks on the thread pool, a single q in the calling thread: the same
    numbers."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-np.pi, np.pi, (3, PARALLEL_BATCH // 2 + 1, chain.n))
    offsets = rng.uniform(-0.1, 0.1, q.shape[:-1] + (3,))
    fk, frames, jac = chain.fk(q), chain.frames(q), chain.jacobian(q, frame=chain.n, offset=offsets)
    assert fk.shape == q.shape[:-1] + (4, 4) and jac.shape == q.shape[:-1] + (6, chain.n)
    for i, j in ((0, 0), (1, 17), (2, q.shape[1] - 1)):
        np.testing.assert_array_equal(fk[i, j], chain.fk(q[i, j]))
        np.testing.assert_array_equal(frames[i, j], chain.frames(q[i, j]))
        np.testing.assert_array_equal(jac[i, j], chain.jacobian(q[i, j], frame=chain.n, offset=offsets[i, j]))


def test_results_do_not_depend_on_the_thread_count(monkeypatch):
    monkeypatch.setattr(_compiled, "POOL_SECONDS", 0.0)  # on the pool however short the batch
    chain = SerialChain(a=[0.1, 0.3, 0.0, 0.2], alpha=[np.pi / 2, 0.3, -np.pi / 2, 0.0], d=[0.2, 0.0, 0.1, 0.05])
    q = np.random.default_rng(1).uniform(-np.pi, np.pi, (5000, 4))
    try:
        results = []
        for count in (1, 2, 3):  # in the calling thread; 8 and 12 chunks on the pool
            set_threads(count)
            results.append((chain.fk(q), chain.frames(q), chain.jacobian(q)))
    finally:
        set_threads(None)
    for other in results[1:]:
        for one, same in zip(results[0], other):
            np.testing.assert_array_equal(one, same)


def test_a_chunk_of_a_batch_writes_its_rows_alone():
    """The batch kernels compute items start .. stop - 1: any split of a batch gives the whole batch's numbers."""
    chain = SerialChain(a=[0.1, 0.3, 0.2], alpha=[np.pi / 2, 0.0, -np.pi / 2], d=[0.2, 0.0, 0.1])
    q = np.random.default_rng(5).uniform(-np.pi, np.pi, (300, 3))
    whole = np.empty((300, 5, 4, 4))
    _chain_kernels.frames(0, 300, q, chain._links, chain._ends, chain._standard, whole)
    parts = np.full((300, 5, 4, 4), np.nan)
    for start, stop in ((0, 1), (1, 38), (38, 38), (38, 299), (299, 300)):
        _chain_kernels.frames(start, stop, q, chain._links, chain._ends, chain._standard, parts)
    np.testing.assert_array_equal(parts, whole)
    np.testing.assert_array_equal(whole, chain.frames(q))
    jac = np.full((300, 6, 3), np.nan)
    _chain_kernels.jacobian(5, 7, q, chain._links, chain._ends, chain._standard, 3, True, np.zeros((1, 3)), jac)
    assert np.isnan(jac[:5]).all() and np.isnan(jac[7:]).all()
    np.testing.assert_array_equal(jac[5:7], chain.jacobian(q[5:7]))


def test_degenerate_chains_and_batches():
    # every length zero: a pure rotation, the origin never moves
    spin = SerialChain(a=[0, 0, 0], alpha=[np.pi / 2, -np.pi / 2, np.pi], d=[0, 0, 0])
    q = np.array([0.3, -1.2, 2.0])
    np.testing.assert_array_equal(spin.fk(q)[:3, 3], 0.0)
    np.testing.assert_allclose(spin.fk(q), reference_frames(spin, q)[-1], atol=1e-15)
    np.testing.assert_array_equal(spin.jacobian(q)[:3], 0.0)
    # one joint, standard and modified
    for convention in ("dh", "mdh"):
        one = SerialChain(a=[0.5], alpha=[0.0], d=[0.0], convention=convention)
        np.testing.assert_allclose(one.fk([np.pi / 2])[:3, 3], [0.0, 0.5, 0.0] if convention == "dh" else [0.5, 0, 0],
                                   atol=1e-16)
    # quarter turns give exact zeros at q = 0
    arm = SerialChain(a=[0, 0.4, 0], alpha=[np.pi / 2, 0, -np.pi / 2], d=[0.3, 0, 0])
    pose = arm.fk(np.zeros(3))
    np.testing.assert_array_equal(pose, np.array([[1, 0, 0, 0.4], [0, 1, 0, 0], [0, 0, 1, 0.3], [0, 0, 0, 1.0]]))
    # empty batches keep their shapes
    assert arm.fk(np.zeros((0, 3))).shape == (0, 4, 4)
    assert arm.frames(np.zeros((2, 0, 3))).shape == (2, 0, 5, 4, 4)
    assert arm.jacobian(np.zeros((0, 3))).shape == (0, 6, 3)
    # the base frame's Jacobian is zero; non-contiguous input is read correctly
    np.testing.assert_array_equal(arm.jacobian(np.ones(3), frame=0), 0.0)
    wide = np.random.default_rng(2).uniform(-1, 1, (400, 6))
    np.testing.assert_array_equal(arm.fk(wide[:, ::2]), arm.fk(np.ascontiguousarray(wide[:, ::2])))


def test_link_table_rows():
    arm = SerialChain(a=[0.1, 0.2], alpha=[np.pi / 2, 0.3], d=[0.0, 0.4], offset=[0.5, 0.0], sign=[1, -1])
    table = arm._links
    assert table.flags.c_contiguous and table.shape == (2, len(_chain_kernels.LINK_COLUMNS))
    np.testing.assert_array_equal(table[0], [0.5, 1.0, 0.1, 0.0, 0.0, 1.0])  # quarter turn exact
    np.testing.assert_allclose(table[1], [0.0, -1.0, 0.2, 0.4, np.cos(0.3), np.sin(0.3)], rtol=0, atol=0)
