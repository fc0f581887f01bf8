"""Parameter objects: derived numbers of eq. 11 and eager, explicit rejection of bad input."""

import math

import pytest

from homlimit import Case, Masonry, ParameterError, Wall


def test_derived_numbers_of_eq_11_for_table1_B1():
    case = Case(Wall(H=9, L=6, s=0.5, b=0.5, l=6.0), Masonry(a=0.3, c=0.2, f=0.6))
    assert case.rho == pytest.approx(12.0)          # Table 1: ρ = 12
    assert case.beta == pytest.approx(0.4)          # Table 1: β = 0.4
    assert case.alpha ** 2 == pytest.approx(0.4)    # Table 1: α² = 0.4
    assert case.lam(6.9) == pytest.approx(13.8)     # Table 1: h_v = 6.9 m -> λ_v = 13.8


@pytest.mark.parametrize("kwargs, name", [
    ({"b": -0.5}, "b"), ({"H": 0.0}, "H"), ({"L": float("nan")}, "L"), ({"s": "x"}, "s"),
    ({"l": float("inf")}, "l"), ({"gamma": -1}, "gamma"), ({"g": 0}, "g"),
])
def test_wall_rejects_bad_values_naming_them(kwargs, name):
    with pytest.raises(ParameterError) as e:
        Wall(**kwargs)
    msg = str(e.value)
    assert msg.startswith(f"{name} = ")
    assert repr(next(iter(kwargs.values()))) in msg or "not a number" in msg


@pytest.mark.parametrize("kwargs, name", [({"f": 0.0}, "f"), ({"a": -0.2}, "a"),
                                          ({"c": float("nan")}, "c")])
def test_masonry_rejects_bad_values(kwargs, name):
    with pytest.raises(ParameterError, match=rf"^{name} = .* allowed 0 < {name}"):
        Masonry(**kwargs)


def test_block_taller_than_wall_is_rejected_with_range():
    with pytest.raises(ParameterError, match=r"a = 10\.0 m .* a <= H = 9 m"):
        Case(Wall(), Masonry(a=10.0))


def test_h_outside_the_wall_is_rejected():
    with pytest.raises(ParameterError, match=r"h = 9\.5 .* h <= 9"):
        Case().lam(9.5)


def test_params_are_immutable():
    with pytest.raises(AttributeError):
        Wall().b = 1.0
    assert math.isclose(Masonry().alpha, math.sqrt(0.2 * 0.6 / 0.3))
