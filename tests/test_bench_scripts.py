"""Functions of the benchmark scripts on tiny inputs (the times they return are not checked against targets)."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))

import bench_srs
import bench_velocity

from redkin.models import barrett_wam, get_robot, pa10_7c
from redkin.reproduce import printed
from redkin.velocity import WamFactorisation

WAM = barrett_wam()
FACTOR = WamFactorisation.from_chain(WAM)
Q0 = np.radians(printed.SECTION_4_Q0_DEG)  # paper 003 section 4
TWIST = np.array(printed.SECTION_4_TWIST)


def test_velocity_array_api_table_runs_on_a_batch():
    """Table 1 of bench_velocity.py: its batched column once stopped the script (LAPACK dgelss on a batch)."""
    batch = np.random.default_rng(0).uniform(-np.pi, np.pi, (3, 7))
    rows = bench_velocity.array_api_rows(WAM, FACTOR, Q0, TWIST, batch, calls=1)
    assert [row[0] for row in rows] == ["pinv", "dls", "dls-adaptive", "sc", "sc-exact"]
    assert all(np.isfinite(row[1:]).all() and min(row[1:]) > 0.0 for row in rows)


def test_velocity_places_have_the_advertised_singularity_index():
    """Table 1 of bench_velocity.py times the SC step outside the region, inside it and in the exact band."""
    places = bench_velocity.places(FACTOR, Q0)
    np.testing.assert_allclose([float(FACTOR.index(q)) for q in places.values()], [FACTOR.index(Q0), 0.05, 1e-4],
                               rtol=1e-9)


def test_srs_peer_check_counts_solutions_within_1e9_by_our_fk():
    """bench_srs.py judges every solver with chain.fk: 1e-10 rad off the last joint passes, 1e-8 rad fails."""
    chain = pa10_7c()
    q = np.random.default_rng(2).uniform(chain.lower, chain.upper, (4, 7))
    poses = chain.fk(q)
    assert bench_srs.pose_errors(chain, q, poses).max() < 1e-14
    moved = q + np.array([[0.0], [1e-10], [1e-8], [1e-6]]) * np.eye(7)[6]
    assert bench_srs.passes(chain, moved, poses) == 2


@pytest.mark.slow
def test_srs_feasible_rows_run_on_a_tiny_batch():
    """bench_srs.py's feasible-set rows: every call of the table runs, on one pose and on a batch of three."""
    from redkin.srs import srs_geometry

    chain = pa10_7c()
    geometry = srs_geometry(chain)
    poses = chain.fk(np.random.default_rng(3).uniform(chain.lower, chain.upper, (3, 7)))
    calls = bench_srs.feasible_calls(geometry, poses[0])
    assert len(calls) == 7 and all(call() is not None for _, call in calls)
    rows = bench_srs.feasible_batch_rows(geometry, poses)
    assert len(rows) == 4 and all("pose-branches/s" in value for _, value in rows)


def test_bench_workspace_times_a_whole_map(tmp_path):
    """bench_workspace.py times complete maps (a map it times must have computed every chunk)."""
    pytest.importorskip("zarr")
    import bench_workspace

    seconds, cpu = bench_workspace.timed_map(tmp_path, "tiny", 2, 2)
    assert seconds > 0.0 and cpu > 0.0


# bench_franka.py (issue 24): the frames of the peers, the set comparisons and the correctness counts

PANDA = get_robot("franka-panda")


@pytest.mark.parametrize(("module", "prefix"), [("frankik", "frankik"), ("geofikpy", "GeoFIK"), ("ssik", "ssik")])
def test_franka_peer_frames_close_by_our_fk(module, prefix):
    """Each peer's claimed end frame (frankik's fk and GeoFIK: the hand, frankik's ik_full and ssik: the flange) is
    what it computes: its FK equals ours in that frame, and its IK rows reach our flange pose (median row)."""
    pytest.importorskip(module)
    import bench_franka

    q = bench_franka.configurations(PANDA, 5, np.random.default_rng(4))
    residuals = {name: value for name, value in bench_franka.frame_residuals(PANDA, q).items()
                 if name.startswith(prefix)}
    assert residuals and max(residuals.values()) < 1e-9, residuals


def test_franka_hand_frame_is_the_flange_turned_and_moved():
    """HAND_IN_FLANGE: -pi/4 about the flange's z, then 0.1034 m along it (franka_description's hand TCP)."""
    import bench_franka

    hand = bench_franka.HAND_IN_FLANGE
    np.testing.assert_allclose(hand[:3, :3] @ [1.0, 0.0, 0.0], [np.sqrt(0.5), -np.sqrt(0.5), 0.0], atol=1e-15)
    np.testing.assert_allclose(hand[:3, 3], [0.0, 0.0, 0.1034])
    np.testing.assert_allclose(hand[:3, :3].T @ hand[:3, :3], np.eye(3), atol=1e-15)


@pytest.mark.parametrize(("joint", "centre"), [(1, 0.0), (5, 0.0), (5, np.pi)])
def test_franka_degenerate_families_are_singular_and_in_limits(joint, centre):
    """The degenerate configurations of bench_franka.py lie within the limits and within 1e-6 rad of what their
    labels say: q2 = 0 aligns axes 1 and 3, q6 = 0 or pi makes axes 5 and 7 parallel."""
    import bench_franka

    q = bench_franka.configurations(PANDA, 20, np.random.default_rng(5), joint, centre)
    assert PANDA.within_limits(q).all() and np.abs(q[:, joint] - centre).max() <= bench_franka.NEAR
    directions, _ = PANDA.joint_axes(q)
    pair = (0, 2) if joint == 1 else (4, 6)
    cosine = np.abs(np.sum(directions[:, pair[0]] * directions[:, pair[1]], axis=-1))
    assert np.all(1.0 - cosine < 1e-11)


def test_franka_set_comparisons_count_missed_and_extra_arcs_only():
    """disagreements: a sample counts when the arcs and the dense mask differ away from every endpoint, so a
    missed or an extra arc counts and an endpoint within the margin does not; count_disagreements compares the
    number of branches containing each sample, whatever the branches' order."""
    import bench_franka

    t = np.linspace(0.0, 1.0, 1001)
    inside = (t >= 0.2) & (t <= 0.4)
    assert bench_franka.disagreements([(0.2, 0.4)], inside, t) == 0
    assert bench_franka.disagreements([(0.2 + 1e-12, 0.4 - 1e-12)], inside, t) == 0
    assert bench_franka.disagreements([], inside, t) == 201
    assert bench_franka.disagreements([(0.2, 0.4), (0.7, 0.8)], inside, t) == 99  # the endpoints are samples
    assert bench_franka.disagreements([(0.2, 0.3)], inside, t) == 100
    one = [[(0.1, 0.5)], [], [(0.6, 0.9)]]
    assert bench_franka.count_disagreements(one, [[(0.6, 0.9)], [(0.1, 0.5)]], t) == 0
    assert bench_franka.count_disagreements(one, [[(0.6, 0.9)], [(0.1, 0.3)]], t) == 199


@pytest.mark.parametrize("module", ["frankik", "geofikpy"])
def test_franka_correctness_counts_rows_by_our_fk(module):
    """at_q7_correctness on a peer: every row returned at q's own q7 is judged by our FK, and a configuration
    the peer returns counts as found (GeoFIK returns every in-limit branch; frankik one elbow of two)."""
    pytest.importorskip(module)
    import bench_franka

    solvers, _ = bench_franka.at_q7_solvers(PANDA)
    solver = next(s for s in solvers if s.name.lower().startswith(module[:6]))
    q = bench_franka.configurations(PANDA, 6, np.random.default_rng(6))
    counts = bench_franka.at_q7_correctness(PANDA, solver, q)
    assert counts.rows >= counts.found > 0 and 0 <= counts.wrong <= counts.rows
    if module == "geofikpy":
        assert counts.found == len(q)


def test_franka_table_runs_on_tiny_sizes():
    """bench_franka.py's whole table on tiny sizes: every section has its rows, redkin's included, and redkin's
    sets agree with its densely sampled IK and find the narrow arcs."""
    import bench_franka

    tiny = bench_franka.Sizes(one_pose=2, batch=300, correctness=4, degenerate=2, ssik_solve=1, feasible=2,
                              ssik_feasible=1, samples=500, narrow=2)
    rows = bench_franka.table(tiny)

    def values(label):
        return [value for name, value in rows if name == label]

    assert values("one pose, all solutions at q7: redkin franka.ik")
    assert values("batch 300 poses at their q7: redkin franka.ik")
    assert values("random in-limit q, own q7: redkin franka.ik")[0].startswith("q found 4/4")
    assert values("fr3: random in-limit q, own q7: redkin franka.ik")[0].startswith("q found 4/4")
    dense = values("  redkin sets vs its IK at 500 q7 samples, limits by our check")  # Panda, then FR3
    assert [value.split(" of ")[0] for value in dense] == ["0", "0"]
    assert values("  redkin: limits +-0.0001 rad around a known solution") == ["arc found 2/2", "arc found 1/1"]


# bench_numerical.py (issue 25): the certificate, the targets, and one quick run


def test_numerical_certificate_is_our_fk_at_1e9_within_the_limits():
    """bench_numerical.certified: our FK within 1e-9 m and rad of the target and the joints within the limits;
    1e-10 rad off the last joint passes, 1e-8 fails, a row 1e-9 past a limit fails even on its own pose, NaN fails."""
    import bench_numerical

    chain = bench_numerical.load("iiwa14")
    targets = bench_numerical.problem(chain, 5)
    assert chain.within_limits(targets.q).all() and chain.within_limits(targets.seeds).all()
    np.testing.assert_array_equal(targets.poses, chain.fk(targets.q))
    moved = targets.q + np.array([[0.0], [1e-10], [1e-8], [0.0], [0.0]]) * np.eye(7)[6]
    moved[3] = np.nan
    outside = targets.q[4].copy()
    outside[0] = chain.upper[0] + 1e-9
    moved[4] = outside
    poses = targets.poses.copy()
    poses[4] = chain.fk(outside)
    assert bench_numerical.certified(chain, moved, poses).tolist() == [True, True, False, False, False]


def test_numerical_rotation_error_is_accurate_for_small_angles():
    """bench_numerical.pose_errors measures a 1e-10 rad turn as 1e-10 (an arccos of the trace would say 0)."""
    import bench_numerical

    chain = bench_numerical.load("gen3")
    q = bench_numerical.problem(chain, 3).q
    turned = chain.fk(q)
    turned[..., :3, :3] = turned[..., :3, :3] @ np.array([[1.0, -1e-10, 0.0], [1e-10, 1.0, 0.0], [0.0, 0.0, 1.0]])
    position, angle = bench_numerical.pose_errors(chain, q, turned)
    np.testing.assert_allclose(angle, 1e-10, rtol=1e-5)
    assert position.max() < 1e-15


@pytest.mark.slow
def test_numerical_quick_run_of_one_arm():
    """bench_numerical.py --quick on the xArm7 (ranges of two turns): every row is made, redkin's own flag and our
    certificate agree on every target, and the seeded row returns the solution that made the target."""
    import bench_numerical

    (result,) = bench_numerical.main(["--quick", "--arms", "xarm7", "--mink-targets", "10"])
    redkin = result.rows[0]
    assert redkin.name.startswith("redkin") and redkin.targets == 200
    assert redkin.success == redkin.claimed and result.seeded.success == result.seeded.claimed
    assert result.batch.success == redkin.success and result.same_solution == result.seeded.success
    assert all(row.targets == (10 if row.name.startswith("mink") else 200) for row in result.rows)


# bench_nearly.py (issue 27): the certificate, the pose sets, ssik's frames, and one quick run


def test_nearly_certificate_and_same_solution_checks():
    """bench_nearly.certified: our FK within 1e-9 m and rad (1e-10 rad off the last joint passes, 1e-8 fails);
    distance and distinct_rows compare joints modulo 2 pi, so a row a turn away is the same solution."""
    import bench_nearly

    chain = bench_nearly.ARMS["jaco2"].load()
    q = bench_nearly.in_limits(chain, np.random.default_rng(8), 3)
    moved = q + np.array([[0.0], [1e-10], [1e-8]]) * np.eye(7)[6]
    assert bench_nearly.certified(chain, moved, chain.fk(q)).tolist() == [True, True, False]
    turned = q[0] + 2.0 * np.pi * np.array([1.0, 0.0, -1.0, 0.0, 0.0, 0.0, 1.0])
    rows = np.stack([q[0], turned, q[0] + 2e-6, q[1]])
    assert bench_nearly.distance(rows, q[0]).max() > bench_nearly.SAME
    np.testing.assert_allclose(bench_nearly.distance(rows[:2], q[0]), 0.0, atol=1e-14)
    assert bench_nearly.distinct_rows(rows) == 3 and bench_nearly.distinct_rows(rows[:0]) == 0


@pytest.mark.parametrize(("name", "q4"), [("gen3", 0.0), ("jaco2", np.pi)])
def test_nearly_pose_sets_lie_near_the_stretched_elbow_and_q3_zero(name, q4):
    """The stretched elbow (the neighbour's theta_4 at its elbow phase, where [000 eq. 11]'s shoulder-wrist
    distance is largest) is at q4 = 0 on the Gen3 and pi on the Jaco2; the near sets hold that joint, and q3, within
    1 deg of it and lie within the limits."""
    import bench_nearly

    from redkin.srs import nearly_srs

    arm = nearly_srs(bench_nearly.ARMS[name].load())
    assert bench_nearly.stretched_q4(arm) == pytest.approx(q4, abs=1e-12)
    random, stretched, near_q3 = bench_nearly.pose_sets(arm, 5, 20)
    assert len(random.q) == 5 and len(stretched.q) == len(near_q3.q) == 20
    assert np.abs(stretched.q[:, 3] - q4).max() <= bench_nearly.NEAR
    assert np.abs(near_q3.q[:, 2]).max() <= bench_nearly.NEAR
    np.testing.assert_array_equal(stretched.poses, arm.chain.fk(stretched.q))


@pytest.mark.parametrize(("name", "equal"), [("gen3", False), ("gen3-urdf", True), ("jaco2", True)])
def test_nearly_ssik_frames_are_ours_where_the_script_runs_ssik(name, equal):
    """ssik's gen3_ik and j2s7s300_ik compute our FK of the URDF arms (to 1e-12); the named DH Gen3 differs (the
    URDF's rounded angles), so the script runs ssik on the URDF arms only."""
    pytest.importorskip("ssik")
    import bench_nearly

    spec = bench_nearly.ARMS[name]
    peer = bench_nearly.load_ssik(spec.reference)
    assert not isinstance(peer, str), peer
    residual = bench_nearly.ssik_fk_residual(spec.load(), peer, np.random.default_rng(9), 20)
    assert (residual < 1e-12) == equal and bool(spec.ssik) == equal


@pytest.mark.slow
def test_nearly_quick_run_of_the_jaco2():
    """bench_nearly.py --quick on the Jaco2: every row that redkin marks found passes our certificate, the batch
    returns what one call per pose returns, and ssik's native answers are judged (when ssik is installed)."""
    import bench_nearly

    (result,) = bench_nearly.main(["--quick", "--arms", "jaco2"])
    assert [s.poses for s in result.redkin] == [200, 50, 50]
    assert all(s.uncertified == 0 for s in result.redkin) and result.redkin[0].found >= 190
    assert any(line.startswith("|   one call per pose and the batch") and "200/200" in line for line in result.lines)
    if result.ssik is not None:
        assert [s.poses for s in result.ssik] == [200, 50, 50] and result.ssik_native is not None


def test_nearly_feasible_run_in_parts_is_the_whole_run():
    """bench_nearly.py --feasible --feasible-first: poses 0-1 and then pose 2 flag what poses 0-2 flag in one run,
    naming each pose by its place in the one sequence (so that the issue's 1000 poses x 10^5 arm angles, hours on
    this machine, can be run in parts); each pose's 8 sets come from one feasible_arm_angles_nearly_all, timed."""
    import bench_nearly

    whole = bench_nearly.measure_feasible("gen3", 3, 96, ssik=False)
    parts = [bench_nearly.measure_feasible("gen3", 2, 96, ssik=False),
             bench_nearly.measure_feasible("gen3", 1, 96, first=2, ssik=False)]
    assert whole.pose_branches == sum(part.pose_branches for part in parts) == 24
    assert whole.missed + whole.false == parts[0].missed + parts[0].false + parts[1].missed + parts[1].false
    assert any("places 2-2 of its sequence" in line for line in parts[1].lines)
    ((draw,),) = [result.draws for result in parts[1:]]
    assert draw.kind == "random" and draw.poses == 1 and draw.seconds.shape == (1,) and draw.ssik_native is None
    assert [len(result.draws[0].seconds) for result in (whole, *parts)] == [3, 2, 1]

    def ends(result):  # the row "ends of computed arcs within one spacing of the sampled boundary | a/b (...) |"
        (line,) = [line for line in result.lines if line.startswith("| ends of computed arcs")]
        agreeing, checked = line.split("|")[2].split("(")[0].strip().split("/")
        return np.array([int(agreeing), int(checked)])

    assert ends(whole)[1] > 0
    np.testing.assert_array_equal(ends(whole), ends(parts[0]) + ends(parts[1]))
    assert not np.array_equal(ends(parts[1]), ends(bench_nearly.measure_feasible("gen3", 1, 96, ssik=False)))
    with pytest.raises(SystemExit):
        bench_nearly.main(["--feasible", "--feasible-first", "-1"])
    with pytest.raises(SystemExit):
        bench_nearly.main(["--feasible", "--feasible-poses", "0", "--feasible-near", "0"])


@pytest.mark.parametrize("name", ["gen3", "jaco2", "iiwa14-rosi"])
def test_nearly_feasible_near_draws_lie_next_to_singular_configurations(name):
    """--feasible-near (issue 38): q6 within 1e-6..1e-3 rad of a value where the neighbour's theta_6 is 0 or pi, q2
    the same for theta_2, q4 within 1e-5..1e-2 rad of the real arm's stretched elbow; within the limits; drawn one
    pose at a time, so that a run in parts draws what one run draws."""
    import bench_nearly

    from redkin.srs import nearly_srs

    arm = nearly_srs(bench_nearly.limited(bench_nearly.FEASIBLE_ARMS[name][1]()))
    draws = bench_nearly.feasible_draws(arm, 2, 6)
    assert [d.kind for d in draws] == ["random"] * 2 + [k for k in bench_nearly.DRAWS[1:] for _ in range(6)]
    later = bench_nearly.feasible_draws(arm, 1, 2, first=4)
    assert [(d.kind, d.index) for d in later] == [("random", 4)] + [(k, i) for k in bench_nearly.DRAWS[1:]
                                                                     for i in (4, 5)]
    for d in later:
        (same,) = [e for e in bench_nearly.feasible_draws(arm, 6, 6) if (e.kind, e.index) == (d.kind, d.index)]
        np.testing.assert_array_equal(d.q, same.q)
    q = np.array([d.q for d in draws])
    assert arm.chain.within_limits(q).all()
    theta = arm.neighbour.offset + arm.neighbour.sign * q  # the neighbour's Table 1 angles
    for kind, (joint, (small, large)) in bench_nearly.NEAR_DRAWS.items():
        rows = [k for k, d in enumerate(draws) if d.kind == kind]
        off = theta[rows, joint] - (arm.real_phase if kind == "stretched elbow" else 0.0)
        period = 2.0 * np.pi if kind == "stretched elbow" else np.pi
        gap = np.abs(np.mod(off + period / 2, period) - period / 2)
        assert np.all((gap >= small * (1 - 1e-9)) & (gap <= large * (1 + 1e-9))), (kind, gap)
        np.testing.assert_allclose(np.abs(np.sin(off)), gap, rtol=1e-4)  # the joint sits that far from singular


def test_nearly_feasible_run_reports_each_draw_and_ssik_beside_it():
    """One pose of each draw on the Gen3: a table column per draw, the 8 branches' time per pose, no false run, and
    ssik's native call and feasible-swivel arcs timed on the same poses where ssik is installed."""
    import bench_nearly

    result = bench_nearly.measure_feasible("gen3", 1, 96, near=1)
    assert [d.kind for d in result.draws] == list(bench_nearly.DRAWS)
    assert all(d.poses == 1 and d.pose_branches == 8 and d.seconds.shape == (1,) for d in result.draws)
    assert not result.false and result.pose_branches == 32
    assert result.lines[result.lines.index("| measurement | random | straight wrist | straight shoulder | "
                                           "stretched elbow |") + 1] == "|---|---|---|---|---|"
    try:
        import ssik  # noqa: F401
    except ImportError:
        assert all(d.ssik_native is None for d in result.draws)
    else:
        assert result.ssik.startswith("ssik 8.2") and "gen3_ik" in result.ssik, result.ssik
        assert all(d.ssik_native.shape == (1,) and d.ssik_arcs.shape == (1,) for d in result.draws)
    table = bench_nearly.feasible_table([result])
    assert table[3].startswith("|---|") and [row.split(" | ")[1] for row in table[4:]] == list(bench_nearly.DRAWS)


# docs_figures.py (issue 43): pytest's summary line read back, processes timed from outside


def test_docs_figures_reads_pytest_summary_lines():
    """parse_pytest_summary: the last summary line of the output, with -q or between '=' signs, its counts in pytest's
    order (a singular warning or error counted under the plural, printed back as pytest prints it) and its seconds;
    an output without a summary line is a ValueError."""
    import docs_figures

    quiet = "....s.\n[100%]\n1290 passed, 55 deselected, 3 skipped, 1 warning in 452.12s (0:07:32)\n"
    summary = docs_figures.parse_pytest_summary(quiet)
    assert summary.counts == {"passed": 1290, "deselected": 55, "skipped": 3, "warnings": 1}
    assert summary.seconds == 452.12 and summary.text() == "1290 passed, 55 deselected, 3 skipped, 1 warning"
    decorated = ("=== 3 passed in 0.10s ===\nFAILED tests/test_x.py::test_y\n"
                 "==== 2 failed, 10 passed, 1 error in 3.01s ====")
    assert docs_figures.parse_pytest_summary(decorated) == docs_figures.PytestSummary(
        {"failed": 2, "passed": 10, "errors": 1}, 3.01)
    with pytest.raises(ValueError, match="expected a pytest summary line"):
        docs_figures.parse_pytest_summary("ERROR: file or directory not found: nowhere\n")


def test_docs_figures_counts_a_process_cpu_seconds_and_stops_on_failure():
    """run_process: the CPU seconds a child spends are counted (a child that spins 0.2 s of its own CPU time), its
    output and exit code are kept; with check, a non-zero exit stops the script with the child's stderr."""
    import docs_figures

    spin = "import time\nwhile time.process_time() < 0.2: pass\nprint('spun')"
    process = docs_figures.run_process([sys.executable, "-c", spin])
    assert process.cpu >= 0.2 and process.wall > 0.0 and process.returncode == 0 and process.stdout == "spun\n"
    fail = [sys.executable, "-c", "import sys; sys.exit('no such pose')"]
    assert docs_figures.run_process(fail, check=False).returncode == 1
    with pytest.raises(SystemExit, match="no such pose"):
        docs_figures.run_process(fail)


def test_core_fk_and_jacobian_rows_give_every_call_and_both_limits():
    """bench_core.py's batch FK and Jacobian rows (issue 42): five rates a way, fresh and into one buffer, and the
    arithmetic's and the memory's limits, each a positive number."""
    import bench_core

    rows = bench_core.fk_jacobian_rows(pa10_7c(), bandwidth=10.0, count=2000)
    assert len(rows) == 7 and rows[0][1] == "10.0 GB/s"
    for label in ("FK", "Jacobian"):
        calls = [row for row in rows if row[0].startswith(f"batch {label},")]
        assert [row[0].rsplit(", ", 1)[1] for row in calls] == ["a fresh result each call", "into one out= buffer"]
        assert all(len(row[1].split()) == 6 and min(float(v) for v in row[1].split()[:5]) > 0.0 for row in calls)
        limits = next(row for row in rows if row[0].startswith(f"  {label} limits"))
        assert float(limits[1].split()[0]) > 0.0 and "memory (" in limits[2]
