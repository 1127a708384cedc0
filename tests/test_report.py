"""partmesh.compare.report: one table for runs of one scene, refusals of runs that
cannot be compared, and the Richardson value and GCI of measured quantities."""

import numpy as np
import pandas as pd
import pytest

import partmesh
from partmesh.compare.report import IncompatibleResults, grid_convergence, report, table

SOD = partmesh.scene("sod", nx_out=100)


@pytest.fixture(scope="module")
def sod_runs():
    return [partmesh.run(SOD, "fv", dx=dx, progress=False) for dx in (1 / 50, 1 / 400)]


def test_runs_of_different_resolutions_are_compared_on_the_scenes_grid(sod_runs):
    # a 50-cell and a 400-cell run, both written on the scene's 100-cell output grid
    coarse, fine = sod_runs
    assert coarse.attrs["regrid"] != fine.attrs["regrid"]
    df = table(sod_runs, SOD.exact(coarse.time.values), ["coarse", "fine"])
    assert list(df["dx"]) == [1 / 50, 1 / 400]
    assert df["rho_L1"][1] < 0.5 * df["rho_L1"][0]


def test_runs_of_a_scene_on_another_output_grid_are_refused_in_one_sentence(sod_runs):
    other = partmesh.run(partmesh.scene("sod", nx_out=200), "fv", dx=1 / 200, progress=False)
    with pytest.raises(IncompatibleResults, match=r"^b is a run of a different scene than a \(they differ in nx_out\)\.$"):
        table([sod_runs[0], other], names=["a", "b"])
    # the same scene parameters but other coordinates (a file edited by hand, say)
    moved = sod_runs[1].assign_coords(x=sod_runs[1].x + 1e-3)
    with pytest.raises(IncompatibleResults, match=r"^b is not on the same output grid as a \(coordinate x\)\.$"):
        table([sod_runs[0], moved], names=["a", "b"])


def test_grid_convergence_of_a_second_order_quantity_is_exact():
    # f(h) = 2 + 0.5 h² on h = 1, 2, 4: p = 2 and the Richardson value 2 exactly, GCI_fine = 1.25 |f1 - f2|/f1/3;
    # a failed run and a method with two levels take no part; a quantity equal on every level has no row
    h = np.array([1.0, 2.0, 4.0, 0.5, 1.0, 2.0])
    df = pd.DataFrame({"method": ["fv"] * 4 + ["sph"] * 2, "dx": h, "status": ["ok"] * 3 + ["failed"] + ["ok"] * 2,
                       "q": 2.0 + 0.5 * h**2, "q_exact": 2.0})
    conv = grid_convergence(df, ["q", "q_exact"])
    assert len(conv) == 1 and conv["method"][0] == "fv" and conv["quantity"][0] == "q"
    row = conv.iloc[0]
    assert (row["dx1"], row["dx2"], row["dx3"]) == (1.0, 2.0, 4.0)
    assert row["p"] == pytest.approx(2.0, rel=1e-12)
    assert row["f_ext"] == pytest.approx(2.0, rel=1e-12)
    assert row["gci_fine"] == pytest.approx(1.25 * (1.5 / 2.5) / 3.0, rel=1e-12)
    assert row["convergence_ratio"] == pytest.approx(0.25, rel=1e-12)


def test_grid_convergence_flags_levels_that_do_not_converge():
    df = pd.DataFrame({"method": ["fv"] * 3, "dx": [1.0, 2.0, 4.0], "status": "ok", "q": [1.0, 2.0, 2.5]})
    row = grid_convergence(df, ["q"]).iloc[0]
    assert row["convergence_ratio"] == pytest.approx(2.0)
    assert "do not converge" in row["note"]


@pytest.mark.full
def test_report_extrapolates_blast_wall_loads_towards_the_fine_grid(tmp_path):
    # FV at 4, 2 and 1 mm: the Richardson values of the wall impulse, arrival time and fitted peak
    # lie closer to a 0.25 mm run than the 1 mm run does, and the 1 mm run is within its GCI of it
    scene = partmesh.scene("blast_wall")
    runs = [partmesh.run(scene, "fv", dx=dx, progress=False) for dx in (4e-3, 2e-3, 1e-3)]
    fine = partmesh.run(scene, "fv", dx=2.5e-4, progress=False)
    report(runs, None, ["4 mm", "2 mm", "1 mm"], tmp_path)
    conv = pd.read_csv(tmp_path / "convergence.csv").set_index("quantity")
    assert (tmp_path / "richardson.png").stat().st_size > 0
    for quantity in ("wall_impulse_final", "wall_arrival_time", "wall_peak_pressure_fitted"):
        row, best = conv.loc[quantity], fine.attrs[quantity]
        assert row["f1"] == runs[2].attrs[quantity] and row["f3"] == runs[0].attrs[quantity]
        assert abs(row["f_ext"] - best) < abs(row["f1"] - best), quantity
        assert abs(row["f1"] / best - 1.0) <= row["gci_fine"], quantity


def test_a_short_run_is_timed_as_the_best_of_its_repeats(tmp_path):
    """The same run three times: its time the least of the three, each
    listed, and the file keeps them; a run over the limit is made once."""
    from partmesh.compare.io import read, write
    from partmesh.dispatch import best_timed_run

    ds = best_timed_run("sod", "fv", repeats=3, short=60.0, dx=0.02, progress=False)
    assert len(ds.attrs["wall_seconds_runs"]) == 3
    assert ds.attrs["wall_seconds"] == min(ds.attrs["wall_seconds_runs"])
    assert ds.attrs["timing"] == "solver time, best of 3 runs"
    write(ds, tmp_path / "r.nc")
    assert list(read(tmp_path / "r.nc").attrs["wall_seconds_runs"]) == ds.attrs["wall_seconds_runs"]
    long = best_timed_run("sod", "fv", short=0.0, dx=0.02, progress=False)
    assert len(long.attrs["wall_seconds_runs"]) == 1 and "one run" in long.attrs["timing"]
