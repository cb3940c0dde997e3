"""Errors arrive as exceptions that say what to fix and carry the typed error's
fields; a failed run keeps what it computed."""

import pickle

import numpy as np
import pytest

import filippov


def test_parameters_are_checked_by_name():
    with pytest.raises(TypeError, match="unexpected parameter `mass`.*m, k, f_crit, eta"):
        filippov.BinghamOscillator(mass=1.0, k=1.0, f_crit=0.1, eta=0.2)
    with pytest.raises(TypeError, match="missing parameters k, eta"):
        filippov.BinghamOscillator(m=1.0, f_crit=0.1)
    with pytest.raises(TypeError, match="`m` must be a number"):
        filippov.BinghamOscillator(m="heavy", k=1.0, f_crit=0.1, eta=0.2)
    with pytest.raises(filippov.ParameterError) as e:
        filippov.BinghamOscillator(m=-1.0, k=1.0, f_crit=0.1, eta=0.2)
    assert isinstance(e.value, filippov.FilippovError)
    assert any("m" in what for what, _ in e.value.problems)


def test_shapes_are_checked_against_the_coordinates():
    arm = filippov.Panda(g=9.81)
    with pytest.raises(ValueError, match=r"Panda has 7 coordinates \(j1, j2"):
        arm.mass_matrix(np.zeros(6))
    with pytest.raises(ValueError, match="same shape"):
        arm.forward_dynamics(np.zeros((3, 7)), np.zeros(7))
    with pytest.raises(KeyError, match="no frame `hand`"):
        arm.frame_pose("hand", np.zeros(7))


def test_options_are_checked_by_name():
    block = filippov.CoulombOscillator(m=1.0, k=1.0, f_crit=0.1)
    with pytest.raises(TypeError, match="unexpected option `rtoll`"):
        block.solve_nonsmooth(1.0, [1.0], rtoll=1e-6)
    with pytest.raises(ValueError, match="no method `euler`"):
        block.solve_nonsmooth(1.0, [1.0], method="euler")
    with pytest.raises(ValueError, match="give it as h="):
        block.solve_nonsmooth(1.0, [1.0], method="time_stepping")
    with pytest.raises(TypeError, match="option `rtol` must be a f64"):
        block.solve_nonsmooth(1.0, [1.0], rtol="tight")


def test_a_failed_run_keeps_its_rows():
    pend = filippov.DoublePendulum(m1=1.0, l1=1.0, m2=0.5, l2=0.7, g=9.81)
    with pytest.raises(filippov.SolveError) as e:
        pend.solve(10.0, [1.2, -0.6], max_steps=20)
    err = e.value
    assert err.kind == "MaxSteps"
    assert err.t == err.solution.t[-1] > 0.0
    assert len(err.solution) > 1 and err.solution.y.shape[1] == 4
    assert "max_steps" in str(err)


def test_a_scene_with_elements_is_not_run_as_smooth():
    block = filippov.CoulombOscillator(m=1.0, k=1.0, f_crit=0.1)
    with pytest.raises(filippov.SolveError, match="friction") as e:
        block.solve(1.0, [1.0])
    assert e.value.kind == "InvalidInput"


def test_integrator_errors_keep_the_run():
    block = filippov.CoulombOscillator(m=1.0, k=1.0, f_crit=0.1)
    run = block.integrator(5.0, [1.0])
    run.advance_to(1.0)
    with pytest.raises(filippov.SolveError) as e:
        run.set_input([float("nan")])
    assert e.value.solution.t[-1] == 1.0
    assert run.solution().t[-1] == 1.0


def test_solution_reads_back():
    block = filippov.CoulombOscillator(m=1.0, k=1.0, f_crit=0.1)
    sol = block.solve_nonsmooth(5.0, [1.0])
    with pytest.raises(KeyError, match="the columns are t, q_x"):
        sol["q_y"]
    with pytest.raises(ValueError, match="outside the run"):
        sol.at(6.0)
    assert sol.at(2.5).shape == (3,) and sol.at([1.0, 2.0]).shape == (2, 3)
    assert sol.stats["steps"] > 0
    assert repr(sol).startswith("Solution(")


def test_scenes_pickle_by_their_parameters():
    arm = filippov.PandaS9(g=9.81, friction=0.7, e=0.2)
    back = pickle.loads(pickle.dumps(arm))
    assert back.parameters == arm.parameters and type(back) is type(arm)


def test_to_pandas():
    pd = pytest.importorskip("pandas")
    sol = filippov.CoulombOscillator(m=1.0, k=1.0, f_crit=0.1).solve_nonsmooth(2.0, [1.0])
    df = sol.to_pandas()
    assert list(df.columns) == ["t"] + sol.names and len(df) == len(sol)
    assert isinstance(pd.DataFrame(sol.switches), pd.DataFrame)
