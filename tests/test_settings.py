"""Every method's settings, fed what a user may type (property tests): on
the path the command line takes (``--option key=value`` reaches
:meth:`partmesh.cases.method.Method.checked` as text), a value is either converted
to its declared type and checked, or refused with one
:class:`~partmesh.cases.errors.InputError` sentence; never another exception.
Settings that are accepted then run a few steps of a small scene, which
ends with a result or a clean :class:`~partmesh.cases.errors.SolverFailed`."""

from __future__ import annotations

import dataclasses
import typing

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import partmesh
from partmesh.cases.errors import InputError, SolverFailed
from partmesh.cases.registry import method as registered
from partmesh.cases.registry import methods
from partmesh.cases.settings import RUN_CONTROLS
from partmesh.gridref.euler.method import LIMITER_NAMES, RIEMANN_NAMES
from partmesh.gridref.swe.method import PRECISION_NAMES
from partmesh.hybrid.cells import SENSORS
from partmesh.particle.dsmc.method import COLLISIONS
from partmesh.particle.kernels import KERNELS

METHODS = ("fv", "swe", "sph", "wcsph", "dsmc", "hybrid")
#: a small scene of each method's medium, its dx and an end time a few steps into it
SMALL = {"gas": ("sod", 1 / 40, 0.01), "water": ("standing_wave", None, 0.05)}
#: names the settings choose among, and the words of a flag
WORDS = (*LIMITER_NAMES, *RIEMANN_NAMES, *PRECISION_NAMES, *KERNELS, *COLLISIONS, *SENSORS, "equal", "lattice",
         "true", "false", "yes", "0", "1")

numbers = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10**12, 10**12),
                    st.floats(-2.0, 20.0), st.integers(-3, 40), st.booleans(),
                    st.sampled_from([float("inf"), float("-inf"), float("nan"), 1e300, -0.0, 0.5]))
#: what may reach a setting: text as typed (numbers too), or a value given in Python
values = st.one_of(numbers.map(str), st.text(max_size=12), st.sampled_from(WORDS), numbers, st.none())


def _settable(method: str) -> list[str]:
    """The settings a drawn value may go to (not the files a run writes)."""
    return [f.name for f in dataclasses.fields(registered(method).settings)
            if f.name not in ("checkpoint", "particles")]


def _one_sentence(error: Exception) -> bool:
    text = str(error)
    return "\n" not in text and text.endswith((".", ")")) and len(text) < 400


def _typed(method, checked) -> None:
    """Every setting of ``checked`` has the type its field declares."""
    hints = typing.get_type_hints(type(checked))
    for f in dataclasses.fields(checked):
        value, hint = getattr(checked, f.name), hints[f.name]
        allowed = typing.get_args(hint) or (hint,)
        allowed = tuple(type(None) if a is None else a for a in allowed)
        assert isinstance(value, allowed), (method, f.name, value, hint)
        if isinstance(value, float):
            assert value == value, (method, f.name)  # (no NaN gets through)


@pytest.mark.full
@pytest.mark.parametrize("method", METHODS)
@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_settings_are_typed_or_refused_in_one_sentence(method, data):
    chosen = registered(method)
    case, _, _ = SMALL[chosen.medium]
    names = _settable(method)
    given_ = data.draw(st.dictionaries(st.sampled_from(names), values, max_size=4))
    if data.draw(st.booleans()):
        given_[data.draw(st.text(min_size=1, max_size=8))] = "1"  # (a setting the method may not have)
    try:
        checked = chosen.checked(partmesh.scene(case), given_)
    except InputError as error:
        assert _one_sentence(error), str(error)
        return
    _typed(method, checked)
    for name, value in given_.items():
        assert value is None or name in names  # (an unknown name is refused)


@pytest.mark.parametrize("method", METHODS)
@settings(max_examples=4, deadline=None)
@given(data=st.data())
def test_accepted_settings_run_a_few_steps(method, data):
    chosen = registered(method)
    case, dx, t_end = SMALL[chosen.medium]
    names = [n for n in _settable(method) if n not in (*RUN_CONTROLS, "dx", "t_end")]
    given_ = data.draw(st.dictionaries(st.sampled_from(names), values, max_size=3))
    given_.update(t_end=t_end, progress=False, **({} if dx is None else {"dx": dx}))
    if method == "dsmc":
        given_["ppc"] = 5  # (a few particles are enough to take steps)
    try:
        ds = partmesh.run(case, method, **given_)
    except (InputError, SolverFailed) as error:
        assert _one_sentence(error), str(error)
        return
    assert ds.attrs["status"] == "ok" and ds.attrs["n_steps"] >= 1


def test_the_registered_methods_are_the_six_with_their_media():
    declared = {m: (registered(m).medium, registered(m).takes_seed) for m in methods()}
    assert declared.items() >= {"fv": ("gas", False), "sph": ("gas", False), "dsmc": ("gas", True),
                                "hybrid": ("gas", False), "swe": ("water", False), "wcsph": ("water", False)}.items()


def test_the_grid_kernels_offer_the_choices_the_settings_name():
    from partmesh.gridref.euler.reconstruct import LIMITERS
    from partmesh.gridref.euler.riemann import RIEMANN_SOLVERS
    from partmesh.gridref.swe.step import PRECISIONS

    assert (set(LIMITERS), set(RIEMANN_SOLVERS), set(PRECISIONS)) == (set(LIMITER_NAMES), set(RIEMANN_NAMES),
                                                                       set(PRECISION_NAMES))


@pytest.mark.parametrize("method", ["sph", "hybrid"])
def test_a_support_too_small_for_the_density_solve_is_refused(method):
    """With η at or below the kernel's least_eta the summation density has no
    solution and the supports would collapse to NaN inside the neighbour
    search: the settings refuse it in one sentence; just above it, sph runs."""
    with pytest.raises(InputError, match=r"^eta must exceed 1\.875 with the wendland_c6 kernel in 1D") as error:
        registered(method).checked(partmesh.scene("sod"), {"eta": "1.5"})
    assert _one_sentence(error.value)
    if method == "sph":
        ds = partmesh.run("sod", "sph", eta=1.9, dx=1 / 40, t_end=0.01, progress=False)
        assert ds.attrs["status"] == "ok" and ds.attrs["n_steps"] >= 1


def test_text_settings_become_numbers_once():
    """``--option eta=4`` on hybrid (text) gives the number the SPH scheme
    needs; ``eta=abc`` one sentence."""
    hybrid = registered("hybrid")
    assert hybrid.checked(partmesh.scene("sod"), {"eta": "4", "buffer": "3"}).eta == 4.0
    with pytest.raises(InputError, match=r"^eta must be a finite number, got 'abc'\.$"):
        hybrid.checked(partmesh.scene("sod"), {"eta": "abc"})
