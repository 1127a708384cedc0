"""The blast-array scene (SPEC §4.2): the geometry of its rods, equal
blockage for every shape, and the inputs it refuses."""

import numpy as np
import pytest

import partmesh
from partmesh.cases.blast import ROW_PITCH
from partmesh.cases.errors import InputError
from partmesh.cases.shape_factories import SHAPES
from partmesh.cases.shape_queries import overlaps

SIZE = 0.0267


def _columns(scene):
    """The rods grouped by column (by their centre's x), upstream first."""
    xs = [0.5 * (r.bounds()[0] + r.bounds()[2]) for r in scene.obstacles]
    keys = np.round(xs, 9)
    return [[r for r, k in zip(scene.obstacles, keys) if k == key] for key in sorted(set(keys))]


def _covered(column, width):
    """The length of [0, width] that a column's rods cover in y (their frontal extent)."""
    edges = sorted((max(r.bounds()[1], 0.0), min(r.bounds()[3], width)) for r in column)
    total, reach = 0.0, 0.0
    for lo, hi in edges:
        total += max(0.0, hi - max(lo, reach))
        reach = max(reach, hi)
    return total


@pytest.mark.parametrize("shape", sorted(SHAPES))
@pytest.mark.parametrize("arrangement", ["inline", "staggered"])
def test_every_shape_and_arrangement_blocks_two_thirds_of_the_channel(shape, arrangement):
    scene = partmesh.scene("blast_array", shape=shape, arrangement=arrangement)
    width = scene.domain[1][1]
    assert width == pytest.approx(3 * ROW_PITCH)
    columns = _columns(scene)
    assert len(columns) == 3
    for column in columns:
        assert _covered(column, width) == pytest.approx(3 * SIZE, rel=1e-9)  # blockage n_rows ζ / W = 2/3
    # the downstream face of the last column stands off 0.34 m from the wall
    assert max(r.bounds()[2] for r in scene.obstacles) == pytest.approx(1.0 - 0.34, abs=1e-12)
    assert not any(overlaps(a, b) for k, a in enumerate(scene.obstacles) for b in scene.obstacles[k + 1:])


def test_staggered_columns_are_shifted_by_half_a_pitch_and_cut_by_the_periodic_sides():
    scene = partmesh.scene("blast_array", arrangement="staggered", layers=4)
    columns = _columns(scene)
    centres = [sorted(0.5 * (r.bounds()[1] + r.bounds()[3]) for r in column) for column in columns]
    np.testing.assert_allclose(centres[0], (np.arange(3) + 0.5) * ROW_PITCH)
    np.testing.assert_allclose(centres[1], np.arange(4) * ROW_PITCH)  # the rods at 0 and W: one rod, cut in two
    np.testing.assert_allclose(centres[2], centres[0])
    np.testing.assert_allclose(centres[3], centres[1])


def test_a_trap_gap_moves_the_upstream_half_of_the_layers_upstream():
    scene = partmesh.scene("blast_array", shape="square", layers=6, trap_gap=0.08, standoff=0.17, blast="strong")
    x = [0.5 * (c[0].bounds()[0] + c[0].bounds()[2]) for c in _columns(scene)]
    np.testing.assert_allclose(np.diff(x), [0.04, 0.04, 0.12, 0.04, 0.04])
    assert x[-1] + 0.5 * SIZE == pytest.approx(1.0 - 0.17)
    assert scene.t_end == 2e-3  # the strong blast's default


def test_more_layers_are_added_upstream():
    three, seven = (partmesh.scene("blast_array", layers=n) for n in (3, 7))
    assert max(r.bounds()[2] for r in seven.obstacles) == max(r.bounds()[2] for r in three.obstacles)
    assert min(r.bounds()[0] for r in seven.obstacles) == pytest.approx(
        min(r.bounds()[0] for r in three.obstacles) - 4 * 0.04)


@pytest.mark.parametrize("settings, message", [
    ({"size": 0.04}, r"^size must lie in \(0, 0\.04\)"),
    ({"shape": "star"}, r"^shape must be"),
    ({"arrangement": "random"}, r"^arrangement must be"),
    ({"column_pitch": 0.02}, r"^column_pitch = 0\.02 m is too small for circle rods"),
    ({"layers": 3, "trap_gap": 0.05}, r"^a trap_gap splits the layers into two equal sets: layers must be even"),
    ({"layers": 9, "column_pitch": 0.05}, r"^the array starts at x = .* upstream of the probe u"),
    ({"standoff": 0.1}, r"^standoff = 0\.1 m puts the array over the probe d"),
])
def test_bad_geometry_is_refused_in_one_sentence(settings, message):
    with pytest.raises(InputError, match=message):
        partmesh.scene("blast_array", **settings)


@pytest.mark.full
def test_sph_joins_rods_cut_by_the_periodic_sides():
    """A staggered array repeats every row pitch, and its rods cut by the
    periodic sides y = 0 and y = W are the two halves of one rod: the SPH
    flow at rest around them is periodic with the row pitch to round-off
    (it differs by 1e-3 in density where the wall particles at the seam
    see the fluid on one side only)."""
    scene = partmesh.scene("blast_array", arrangement="staggered")
    ds = partmesh.run(scene, "sph", dx=2e-3, t_end=4e-5, progress=False)
    rho = ds["rho"].isel(time=-1).sel(x=slice(0.5, 0.75)).values
    rows = int(round(ROW_PITCH / float(ds.y[1] - ds.y[0])))
    assert rho.shape[0] == 3 * rows
    assert np.nanmax(np.abs(rho[:rows] - rho[rows:2 * rows])) < 1e-10
    assert np.nanmax(np.abs(rho[rows:2 * rows] - rho[2 * rows:])) < 1e-10
