"""The bracket of a root narrowed from outside the neighbourhood where evaluations fail
(shellbvp.continuation.squeeze): the root of a known function, its evaluations refused
within a stated distance of the root, as solves next to a branch point whose symmetry the
discretisation breaks are."""

import pytest

from shellbvp.continuation.squeeze import narrowest_sign_change, squeeze

ROOT, DEAD = 0.3141592653589793, 1e-7


class Refused(Exception):
    pass


def test_the_bracket_shrinks_to_the_neighbourhood_where_evaluations_fail():
    log = {}

    def f(x):
        if abs(x - ROOT) < DEAD:
            raise Refused(x)
        log[x] = (x - ROOT) * (1 + x)          # a simple root at ROOT
        return log[x]

    f(0.0), f(1.0)
    squeeze(f, list(log.items()), floor=1e-14, errors=(Refused,))
    (a, _), (b, _) = narrowest_sign_change(log.items())
    assert a < ROOT < b
    # false position until a step falls within DEAD of the root, then probes toward it at
    # distances shrinking by 8: the last accepted on either side lies within 8 DEAD of it
    assert b - a < 20 * DEAD, (a, b)


def test_nothing_is_evaluated_without_a_sign_change_or_below_the_floor():
    calls = []

    def f(x):
        calls.append(x)
        return 1.0

    squeeze(f, [(0.0, 1.0), (1.0, 2.0)], floor=1e-12, errors=(Refused,))
    assert calls == []
    squeeze(f, [(0.0, -1.0), (1.0, 1.0)], floor=10.0, errors=(Refused,))
    assert calls == []


def test_without_failures_it_narrows_to_the_floor():
    log = {}

    def f(x):
        log[x] = x ** 3 - 0.2
        return log[x]

    f(0.0), f(1.0)
    squeeze(f, list(log.items()), floor=1e-9, errors=(Refused,))
    (a, _), (b, _) = narrowest_sign_change(log.items())
    assert a < 0.2 ** (1 / 3) < b and b - a <= 1e-9


def test_an_error_it_was_not_told_of_propagates():
    def f(x):
        raise KeyError(x)

    with pytest.raises(KeyError):
        squeeze(f, [(0.0, -1.0), (1.0, 1.0)], floor=1e-12, errors=(Refused,))
