"""Ensembles give one table whatever runs them: rayon on every core, a plain loop, and
a real Dask cluster of two worker processes, bit for bit; failed runs stay in it."""

import pickle

import numpy as np
import pytest

import filippov
from filippov import ensembles

ARM = dict(m1=1.0, l1=1.0, m2=0.5, l2=0.7, fc=2.0, lim=-1.0, e=0.5)


def arm_ensemble(samples, seed=3, **draws):
    arm = filippov.RestingArm(**ARM)
    parameters = draws or {"fc": ("uniform", 0.5, 20.0), "e": ("uniform", 0.0, 0.9)}
    return arm.ensemble(5.0, parameters=parameters, q0=[0.2, ("uniform", -1.0, 1.0)], samples=samples, seed=seed)


@pytest.fixture(scope="module")
def cluster():
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster, distributed.Client(cluster) as client:
        yield client


def test_ten_thousand_runs_same_table_on_rayon_loop_and_dask(cluster, tmp_path):
    ens = arm_ensemble(10_000)
    assert len(ens) == 10_000
    on_cores = ensembles.run(ens)
    looped = ensembles.run(ens, "loop")
    on_dask = ensembles.run(ens, "dask", client=cluster, chunk=500)
    assert on_cores.equals(looped) and on_cores.equals(on_dask)
    # Again, at once: the same ensemble scattered anew while the first copy is released.
    assert ensembles.run(ens, "dask", client=cluster, chunk=2_500).equals(on_cores)
    assert list(on_cores["run"]) == list(range(10_000))
    # The draws cover their ranges, and no run passed the rigid stop.
    assert 0.5 <= on_cores["fc"].min() < 0.6 and 19.9 < on_cores["fc"].max() < 20.0
    ok = ~on_cores.failed
    assert ok.sum() > 9_900
    assert (on_cores["q_shoulder"][ok] >= ARM["lim"]).all()
    # The table survives a round trip through .npz, without pickle.
    on_cores.save(tmp_path / "arm.npz")
    assert ensembles.Table.load(tmp_path / "arm.npz").equals(on_cores)


def test_ray_gives_the_same_table():
    """On a local Ray instance of two CPUs (its own processes)."""
    ray = pytest.importorskip("ray")
    ens = arm_ensemble(2_000)
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False)
    try:
        assert ensembles.run(ens, "ray", chunk=250).equals(ensembles.run(ens))
    finally:
        ray.shutdown()


def test_any_range_is_the_tables_slice_and_seeds_reproduce():
    ens = arm_ensemble(300)
    whole = ensembles.Table(ens.run())
    part = ensembles.Table(ens.run(120, 170, threads=1))
    for k in whole.names:
        a, b = whole[k][120:170], part[k]
        assert a.tobytes() == b.tobytes(), k
    again = ensembles.Table(arm_ensemble(300).run())
    assert again.equals(whole)
    other = ensembles.Table(arm_ensemble(300, seed=4).run())
    assert not np.array_equal(other["fc"], whole["fc"])
    # Pickled (as a cluster sends it), it is the same ensemble.
    assert ensembles.Table(pickle.loads(pickle.dumps(ens)).run(0, 40)).equals(
        ensembles.Table(ens.run(0, 40))
    )


def test_grids_are_a_cartesian_product_in_order():
    arm = filippov.RestingArm(**ARM)
    ens = arm.ensemble(1.0, parameters={"fc": [1.0, 5.0], "e": [0.0, 0.3, 0.6]}, q0=[0.2, -0.5], samples=2)
    t = ensembles.Table(ens.run())
    assert len(t) == 12
    assert list(t["fc"]) == [1.0] * 6 + [5.0] * 6
    assert list(t["e"]) == [0.0, 0.0, 0.3, 0.3, 0.6, 0.6] * 2
    assert (t["m1"] == 1.0).all() and (t["q0_elbow"] == -0.5).all()


def test_failed_runs_are_kept_with_their_error():
    # Negative friction thresholds are refused by the scene; those runs stay, marked.
    ens = arm_ensemble(200, fc=("uniform", -5.0, 5.0))
    t = ensembles.run(ens)
    assert len(t) == 200
    bad = t["fc"] < 0.0
    assert bad.any() and (t.failed == bad).all()
    assert set(t["error_kind"][bad]) == {"InvalidParameters"}
    assert all("fc" in m for m in t["error"][bad])
    assert np.isnan(t["q_shoulder"][bad]).all() and not np.isnan(t["q_shoulder"][~bad]).any()


def test_bad_ensembles_say_what_is_wrong():
    arm = filippov.RestingArm(**ARM)
    with pytest.raises(TypeError, match="no parameter `friction`"):
        arm.ensemble(1.0, parameters={"friction": 1.0})
    with pytest.raises(ValueError, match="q0 has 1 entries for the 2 coordinates"):
        arm.ensemble(1.0, q0=[0.1])
    with pytest.raises(ValueError, match="low ≤ high"):
        arm.ensemble(1.0, parameters={"fc": ("uniform", 2.0, 1.0)})
    with pytest.raises(ValueError, match="no backend"):
        ensembles.run(arm.ensemble(1.0), "spark")
