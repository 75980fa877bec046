"""Property-based checks of the input contract (hypothesis): over the whole range of numbers
a user can type, a Scene is either built with every field inside its documented range, or
refused with a ValueError whose message starts with the name of a parameter it was given
(never another exception, never a Scene out of range)."""

import math

from hypothesis import given, settings, strategies as st

from shellbvp import MATERIALS, MODELS, cap
from shellbvp.scene import H_MIN, LAM_MAX, SCENE_DEFAULTS, THETA_MIN

numbers = st.one_of(st.floats(allow_nan=True, allow_infinity=True),
                    st.floats(min_value=-10, max_value=10),
                    st.sampled_from([0.0, 1e-9, 1e-3, 0.5, 1.0, 3.0, 1e8, 1e9]))


@settings(max_examples=300, deadline=None)
@given(theta=numbers, h=numbers, lam=st.one_of(numbers, st.just(1.0)),
       nu=st.one_of(numbers, st.just(0.5)), model=st.sampled_from(MODELS + ("bogus",)),
       material=st.sampled_from(MATERIALS + ("steel",)))
def test_scene_is_in_range_or_refused_by_name(theta, h, lam, nu, model, material):
    given_ = dict(theta=theta, h=h, lam=lam, nu=nu, model=model, material=material)
    try:
        sc = cap(**given_)
    except ValueError as exc:
        assert str(exc).split()[0].strip("'\"").split("=")[0] in given_, str(exc)
        return
    assert THETA_MIN < sc.length < math.pi and H_MIN < sc.h < 1
    assert sc.model in MODELS and sc.material in MATERIALS
    if sc.material == "cg":
        assert 0 < sc.lam < LAM_MAX and sc.nu == SCENE_DEFAULTS["nu"]
    else:
        assert sc.lam == SCENE_DEFAULTS["lam"] and sc.model == SCENE_DEFAULTS["model"]
    if sc.material == "koiter":
        assert -1 < sc.nu < 1
