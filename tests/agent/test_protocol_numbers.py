"""Number spelling: the server's %.2f and %g (checked against the C library itself), agent floats, parsing."""

from __future__ import annotations

import ctypes
import ctypes.util
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from agent.protocol.errors import ProtocolError
from agent.protocol.numbers import (
    format_agent_float,
    format_fixed2,
    format_g6,
    parse_finite_float,
    parse_float,
    parse_int,
    round_float32,
)

_LIBC = ctypes.CDLL(ctypes.util.find_library("c"))


def c_printf(fmt: str, value: float) -> str:
    """What the C library prints for ``value`` (the server is C++ on glibc)."""
    buffer = ctypes.create_string_buffer(512)
    _LIBC.snprintf(buffer, len(buffer), fmt.encode(), ctypes.c_double(value))
    return buffer.value.decode()


@pytest.mark.parametrize(
    ("value", "expected"),
    [
        (-0.001, "-0.00"),  # small negatives keep their sign, as the sample's "(ax -0.00)"
        (-0.0, "-0.00"),
        (0.004, "0.00"),
        (0.125, "0.12"),  # exact binary tie: half to even
        (0.375, "0.38"),
        (2.675, "2.67"),  # 2.67499999... in binary
        (104.36, "104.36"),
        (-61.93, "-61.93"),
        (1e20, "100000000000000000000.00"),
    ],
)
def test_fixed2_spells_like_the_server(value: float, expected: str) -> None:
    assert format_fixed2(value) == expected
    assert c_printf("%.2f", value) == expected


@given(st.floats(allow_nan=False, allow_infinity=False, min_value=-1e6, max_value=1e6))
def test_fixed2_matches_c_printf(value: float) -> None:
    assert format_fixed2(value) == c_printf("%.2f", value)


@given(st.floats(allow_nan=False, allow_infinity=False, width=32))
def test_g6_matches_c_printf_for_float32_values(value: float) -> None:
    assert format_g6(value) == c_printf("%g", value)


def test_non_finite_values_are_spelled_as_glibc_does() -> None:
    for value in (math.inf, -math.inf, math.nan, -math.nan):
        assert format_fixed2(value) == c_printf("%.2f", value)
        assert format_g6(value) == c_printf("%g", value)


def test_g6_examples_from_the_monitor_sample() -> None:
    assert [format_g6(v) for v in (30.0, 2.1, 0.042, -8.74228e-08, -0.0, 0.0210764)] == [
        "30", "2.1", "0.042", "-8.74228e-08", "-0", "0.0210764"
    ]
    assert format_g6(3) == "3"


@pytest.mark.parametrize(
    ("value", "expected"),
    [(0.5, "0.5"), (-2.5, "-2.5"), (0.0, "0"), (-0.0, "0"), (1.0, "1"), (-1.25, "-1.25"), (1e-4, "0.0001"),
     (1e-5, "0"), (-4e-5, "0"), (0.123456, "0.1235"), (123456789.0, "123456789")],
)
def test_agent_float_is_a_short_plain_decimal(value: float, expected: str) -> None:
    assert format_agent_float(value) == expected


@given(st.floats(allow_nan=False, allow_infinity=False))
def test_agent_float_never_uses_an_exponent_and_reads_back(value: float) -> None:
    text = format_agent_float(value)
    assert "e" not in text and "E" not in text and text != "-0"
    assert abs(float(text) - value) <= 5e-5 + math.ulp(value)  # half the 4th decimal, plus re-rounding


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
def test_agent_float_refuses_non_finite_values(value: float) -> None:
    with pytest.raises(ProtocolError):
        format_agent_float(value)


@pytest.mark.parametrize(
    ("token", "value"),
    [("1", 1.0), ("-0.00", -0.0), ("+2.5", 2.5), (".5", 0.5), ("3.", 3.0), ("1e-3", 1e-3), ("-2E+2", -200.0)],
)
def test_parse_float_accepts_decimals(token: str, value: float) -> None:
    parsed = parse_float(token, 0)
    assert parsed == value and math.copysign(1.0, parsed) == math.copysign(1.0, value)


@pytest.mark.parametrize("token", ["nan", "NaN", "inf", "-inf", "Infinity"])
def test_parse_float_parses_non_finite_so_callers_can_flag_them(token: str) -> None:
    assert not math.isfinite(parse_float(token, 0))
    with pytest.raises(ProtocolError) as error:
        parse_finite_float(token, 12)
    assert error.value.offset == 12


@pytest.mark.parametrize("token", ["", "1_0", " 1", "1 ", "0x10", "1.2.3", "e5", "--1", "nanx", "1e"])
def test_parse_float_rejects_what_float_would_accept_or_garble(token: str) -> None:
    with pytest.raises(ProtocolError) as error:
        parse_float(token, 7)
    assert error.value.offset == 7
    assert "byte 7" in str(error.value)


def test_parse_error_snippet_comes_from_the_message_when_given() -> None:
    message = "(HJ (n hj1) (ax 1.2.3))"
    with pytest.raises(ProtocolError) as error:
        parse_float("1.2.3", 16, message)
    assert error.value.offset == 16
    assert b"1.2.3" in error.value.snippet and b"(HJ" in error.value.snippet


def test_parse_int_is_strict() -> None:
    assert parse_int("-3", 0) == -3
    for token in ("3.0", "1_0", "", "x"):
        with pytest.raises(ProtocolError):
            parse_int(token, 0)


def test_round_float32_rounds_to_single_precision() -> None:
    assert round_float32(0.1) == 0.10000000149011612
    assert round_float32(0.5) == 0.5
