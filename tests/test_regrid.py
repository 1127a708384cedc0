"""Moving fields between cell-centred uniform grids (partmesh.compare.regrid)."""

import numpy as np
import pytest

from partmesh.compare.regrid import to_output_grid


def centres(x0, x1, n):
    """Cell centres of n uniform cells on [x0, x1]."""
    h = (x1 - x0) / n
    return x0 + h * (np.arange(n) + 0.5)


# --- identity ---------------------------------------------------------------


def test_identical_grids_copy():
    x = centres(0.0, 1.0, 8)
    v = np.arange(8.0)
    out, how = to_output_grid(v, x, x.copy())
    assert how == "identity"
    np.testing.assert_array_equal(out, v)
    out[0] = 99.0
    assert v[0] == 0.0  # a copy, not a view


def test_identical_2d_grids_with_batch_axis():
    x, y = centres(0, 1, 5), centres(0, 2, 4)
    v = np.random.default_rng(0).random((3, 4, 5))
    out, how = to_output_grid(v, x, x, y, y)
    assert how == "identity"
    np.testing.assert_array_equal(out, v)


# --- conservative averaging -------------------------------------------------


def test_conservative_constant_and_linear_1d():
    src, dst = centres(0.0, 1.2, 12), centres(0.0, 1.2, 4)  # k = 3
    out, how = to_output_grid(np.full(12, 7.25), src, dst)
    assert how == "conservative average"
    np.testing.assert_array_equal(out, np.full(4, 7.25))
    # the mean of a linear function over a block is its value at the block centre
    out, _ = to_output_grid(2.0 * src + 1.0, src, dst)
    np.testing.assert_allclose(out, 2.0 * dst + 1.0, rtol=0, atol=1e-14)


def test_conservative_block_values_by_hand():
    src, dst = centres(0.0, 1.0, 4), centres(0.0, 1.0, 2)
    out, how = to_output_grid(np.array([1.0, 3.0, 10.0, 20.0]), src, dst)
    assert how == "conservative average"
    np.testing.assert_array_equal(out, [2.0, 15.0])


def test_conservative_preserves_the_integral():
    rng = np.random.default_rng(1)
    src = centres(0.0, 2.0, 40)  # dx = 0.05
    dst = centres(0.2, 1.8, 8)  # dx = 0.2: k = 4, offset 4 source cells
    v = rng.normal(size=(3, 40))
    out, how = to_output_grid(v, src, dst)
    assert how == "conservative average"
    covered = v[:, 4:36]
    np.testing.assert_allclose(out.sum(axis=1) * 0.2, covered.sum(axis=1) * 0.05, rtol=1e-13)


def test_conservative_2d_bilinear_field_and_integral():
    sx, sy = centres(0.0, 1.0, 12), centres(0.0, 0.6, 9)  # dx = 1/12, dy = 1/15
    dx_, dy_ = centres(0.0, 1.0, 6), centres(0.0, 0.6, 3)  # kx = 2, ky = 3
    X, Y = np.meshgrid(sx, sy)
    DX, DY = np.meshgrid(dx_, dy_)
    f = 1.0 + 2.0 * X - 3.0 * Y + 4.0 * X * Y  # tensor-product blocks: mean(xy) = mean(x) mean(y)
    out, how = to_output_grid(f, sx, dx_, sy, dy_)
    assert how == "conservative average"
    assert out.shape == (3, 6)
    np.testing.assert_allclose(out, 1.0 + 2.0 * DX - 3.0 * DY + 4.0 * DX * DY, rtol=0, atol=1e-14)
    g = np.random.default_rng(2).random((2, 9, 12))
    out, _ = to_output_grid(g, sx, dx_, sy, dy_)
    np.testing.assert_allclose(
        out.sum(axis=(1, 2)) * (1 / 6) * 0.2, g.sum(axis=(1, 2)) * (1 / 12) * (1 / 15), rtol=1e-13
    )


def test_conservative_is_nan_aware():
    src, dst = centres(0.0, 1.0, 6), centres(0.0, 1.0, 3)
    v = np.array([1.0, np.nan, np.nan, np.nan, 4.0, 6.0])
    out, how = to_output_grid(v, src, dst)
    assert how == "conservative average"
    assert out[0] == 1.0
    assert np.isnan(out[1])
    assert out[2] == 5.0
    # 2D: a block with one solid cell out of four averages the other three
    s, d = centres(0, 1, 4), centres(0, 1, 2)
    w = np.ones((4, 4))
    w[0, 0] = np.nan
    w[0, 1] = 4.0
    out, _ = to_output_grid(w, s, d, s, d)
    assert out[0, 0] == pytest.approx(2.0, abs=1e-15)  # (4 + 1 + 1)/3
    np.testing.assert_array_equal(out[1], [1.0, 1.0])


# --- linear interpolation ----------------------------------------------------


def test_linear_coarse_to_fine_with_clamping():
    src, dst = centres(0.0, 1.0, 5), centres(0.0, 1.0, 10)  # 0.1, 0.3, ... -> 0.05, 0.15, ...
    out, how = to_output_grid(3.0 * src - 1.0, src, dst)
    assert how == "linear interpolation"
    inner = (dst >= 0.1) & (dst <= 0.9)
    np.testing.assert_allclose(out[inner], 3.0 * dst[inner] - 1.0, rtol=0, atol=1e-14)
    assert out[0] == pytest.approx(3.0 * 0.1 - 1.0, abs=1e-15)  # clamped to the first source centre
    assert out[-1] == pytest.approx(3.0 * 0.9 - 1.0, abs=1e-15)
    out, _ = to_output_grid(np.full(5, -2.5), src, dst)
    np.testing.assert_array_equal(out, np.full(10, -2.5))


def test_non_integer_ratio_and_misaligned_grids_interpolate():
    src = centres(0.0, 1.0, 10)
    out, how = to_output_grid(2.0 * src, src, centres(0.0, 1.0, 4))  # ratio 2.5
    assert how == "linear interpolation"
    np.testing.assert_allclose(out, 2.0 * centres(0.0, 1.0, 4), atol=1e-14)
    shifted = centres(0.05, 0.85, 4)  # ratio 2 but edges half a source cell off
    out, how = to_output_grid(2.0 * src, src, shifted)
    assert how == "linear interpolation"
    np.testing.assert_allclose(out, 2.0 * shifted, atol=1e-14)


def test_bilinear_reproduces_bilinear_fields_2d():
    sx, sy = centres(0, 1, 6), centres(0, 1, 5)
    dx_, dy_ = centres(0.1, 0.9, 7), centres(0.1, 0.9, 9)  # all inside the source centres
    X, Y = np.meshgrid(sx, sy)
    DX, DY = np.meshgrid(dx_, dy_)
    f = 1.0 + 2.0 * X + 3.0 * Y + 4.0 * X * Y
    out, how = to_output_grid(np.stack([f, 2 * f]), sx, dx_, sy, dy_)
    assert how == "linear interpolation"
    expect = 1.0 + 2.0 * DX + 3.0 * DY + 4.0 * DX * DY
    np.testing.assert_allclose(out[0], expect, atol=1e-14)
    np.testing.assert_allclose(out[1], 2 * expect, atol=1e-14)


def test_linear_is_nan_aware():
    src = np.array([0.5, 1.5, 2.5])
    v = np.array([1.0, np.nan, 3.0])
    out, how = to_output_grid(v, src, np.array([0.25, 1.0, 1.75, 2.5]))
    assert how == "linear interpolation"
    # 0.25 clamps to 1; 1.0 sits between 1 and NaN: the NaN corner is dropped -> 1;
    # 1.75 between NaN and 3 -> 3; 2.5 sits on the last centre -> 3
    np.testing.assert_array_equal(out, [1.0, 1.0, 3.0, 3.0])
    # a point on the NaN centre only has no finite corner with weight > 0
    out, _ = to_output_grid(v, src, np.array([1.5]))
    assert np.isnan(out[0])


# --- bad input ---------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs, word",
    [
        (dict(values=np.ones(4), src_x=centres(0, 1, 5), dst_x=centres(0, 1, 2)), "src_x"),
        (dict(values=np.ones(4), src_x=np.array([0.0, 0.1, 0.3, 0.4]), dst_x=centres(0, 1, 2)), "src_x"),
        (dict(values=np.ones(4), src_x=centres(0, 1, 4), dst_x=np.array([0.5, 0.2])), "dst_x"),
        (dict(values=np.ones((3, 4)), src_x=centres(0, 1, 4), dst_x=centres(0, 1, 2), src_y=centres(0, 1, 3)), "dst_y"),
        (dict(values=np.ones((2, 2, 3, 4)), src_x=centres(0, 1, 4), dst_x=centres(0, 1, 2),
              src_y=centres(0, 1, 3), dst_y=centres(0, 1, 3)), "values"),
        (dict(values=np.ones((3, 4)), src_x=centres(0, 1, 4), dst_x=centres(0, 1, 2),
              src_y=centres(0, 1, 2), dst_y=centres(0, 1, 2)), "src_y"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, word):
    with pytest.raises(ValueError, match=word):
        to_output_grid(**kwargs)
