"""Robot-file parser hardening (issue 10, item 7): bad input gets one RobotDefinitionError, always.

The fuzz tests feed the parser random TOML documents and mutations of the shipped robot
files; anything but a robot with finite FK or armkit's own error fails them.
"""

from __future__ import annotations

import os
import re
from importlib import resources

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import armkit
from armkit.errors import RobotDefinitionError

#: Examples per fuzz test; `make fuzz` runs many more (ARMKIT_FUZZ_EXAMPLES).
FUZZ_EXAMPLES = int(os.environ.get("ARMKIT_FUZZ_EXAMPLES", "300"))
FUZZ = settings(max_examples=FUZZ_EXAMPLES, deadline=None,
                suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])

GOOD = """convention = "standard"
length_unit = "mm"
angle_unit = "deg"
[[joints]]
name = "a"
alpha = 0
a = 300
d = 0
theta = 0
[[joints]]
name = "b"
alpha = 0
a = 200
d = 0
theta = 0
"""
SHIPPED = {p.name: p.read_text(encoding="utf-8") for p in (resources.files("armkit") / "robots").iterdir()
           if p.name.endswith(".toml")}


def load_bytes(tmp_path, data: bytes, name="arm.toml"):
    path = tmp_path / name
    path.write_bytes(data)
    return armkit.load(path)


@pytest.mark.parametrize(("text", "message"), [
    (GOOD.replace('length_unit = "mm"', 'length_unit = ["mm"]'),
     r"length_unit = \['mm'\]; expected one of 'm', 'mm'"),
    (GOOD.replace('angle_unit = "deg"', "angle_unit = {a=1}"), r"angle_unit = \{'a': 1\}; expected one of"),
    (GOOD.replace('convention = "standard"', "convention = 3"), r"convention = 3; expected one of"),
    (GOOD.replace('type', 'type').replace("a = 300", 'a = 300\ntype = ["revolute"]'),
     r"joint 1: type = \['revolute'\]; expected one of"),
    (GOOD.replace("a = 300", "a = 1e308"), r"joint 1, key 'a': 1e\+308 is 1e\+305 in SI units \(m or rad\); "
                                           r"expected at most 1e\+06"),
    (GOOD.replace("alpha = 0\na = 300", "alpha = 1e300\na = 300"), r"key 'alpha': 1e\+300 is"),
    (GOOD.replace('name = "b"', 'name = "a"'),
     r"joint 2, key 'name': 'a' is already the name of another joint"),
    (GOOD.replace('name = "b"', 'name = ""'), r"joint 2, key 'name': empty"),
    (GOOD.replace('name = "b"', 'name = "  "'), r"joint 2, key 'name': empty"),
    (GOOD.replace('name = "b"', "name = 7"), r"joint 2, key 'name': expected a string, got 7"),
    (GOOD.replace('name = "b"', 'name = "q1"').replace('name = "a"\n', ""),
     r"joint 2, key 'name': 'q1' is already the name"),
    ('name = ["x"]\n' + GOOD, r"key 'name': expected a string, got \['x'\]"),
    ('description = 1\n' + GOOD, r"key 'description': expected a string, got 1"),
    (GOOD.replace("a = 300", "a = 300\nlimits = [-1e300, 1e300]"), r"key 'limits': -1e\+300 is"),
    (GOOD + "[[tool]]\nalpha = 0\na = 0\nd = 1e307\ntheta = 0\n", r"tool row 1, key 'd': 1e\+307 is"),
])
def test_bad_values_get_one_clear_error(tmp_path, text, message):
    with pytest.raises(RobotDefinitionError, match=message):
        load_bytes(tmp_path, text.encode())


def test_non_utf8_file(tmp_path):
    with pytest.raises(RobotDefinitionError, match=r"arm.toml: not UTF-8 text \(byte 8\); save the robot"):
        load_bytes(tmp_path, b'name = "\xff\xfe"\n' + GOOD.encode())


def test_a_byte_order_mark_is_skipped_as_in_urdf(tmp_path):
    with_mark = load_bytes(tmp_path, b"\xef\xbb\xbf" + GOOD.encode())
    without = load_bytes(tmp_path, GOOD.encode())
    q = without.random_q(4, rng=3)
    np.testing.assert_array_equal(with_mark.fk(q), without.fk(q))
    assert with_mark.joint_names == without.joint_names


def test_arrays_nested_5000_deep(tmp_path):
    text = GOOD.replace("a = 300", "a = " + "[" * 5000 + "]" * 5000)
    with pytest.raises(RobotDefinitionError, match="nested too deeply"):
        load_bytes(tmp_path, text.encode())


def test_lengths_that_overflow_only_together_are_refused(tmp_path):
    """Each length is allowed, their sum at the largest allowed value still gives finite FK."""
    text = GOOD.replace("a = 300", "a = 1e9").replace("a = 200", "a = 1e9")  # 1e6 m each
    robot = load_bytes(tmp_path, text.encode())
    assert np.isfinite(robot.fk(robot.random_q(5, rng=0))).all()
    with pytest.raises(RobotDefinitionError, match="1.1e\\+06 in SI units"):
        load_bytes(tmp_path, text.replace("a = 1e9", "a = 1.1e9", 1).encode())


def test_an_xml_file_is_read_by_its_root_element_not_its_name(tmp_path):
    pytest.importorskip("mujoco")
    with pytest.raises(RobotDefinitionError, match=r"arm.toml: the root element is <sdf>; a URDF file"):
        load_bytes(tmp_path, b"<sdf/>")
    with pytest.raises(RobotDefinitionError, match=r"arm.toml: 0 leaf bodies below 'world'"):  # MJCF
        load_bytes(tmp_path, b"<?xml version='1.0'?><!-- an empty model --><mujoco/>")


# ------------------------------------------------------------------ fuzzing
def check_loads_or_refuses(tmp_path, data: bytes) -> None:
    try:
        robot = load_bytes(tmp_path, data)
    except RobotDefinitionError as exc:
        assert str(exc).strip() and "\n" not in str(exc).strip()
        return
    q = robot.random_q(3, rng=0)
    assert np.isfinite(robot.fk(q)).all()
    assert np.isfinite(robot.jacobian(q)).all()


toml_scalars = st.one_of(
    st.integers(-10**20, 10**20), st.floats(allow_nan=True, allow_infinity=True), st.booleans(),
    st.text(max_size=6), st.sampled_from(["mm", "m", "deg", "rad", "standard", "modified", "poe",
                                          "revolute", "prismatic"]))


def toml_value(scalar_text):
    return st.recursive(scalar_text, lambda inner: st.one_of(
        st.lists(inner, max_size=4).map(lambda v: "[" + ", ".join(v) + "]"),
        st.dictionaries(st.sampled_from(["a", "d", "xyz", "rpy", "matrix", "x"]), inner, max_size=3).map(
            lambda d: "{" + ", ".join(f"{k} = {v}" for k, v in d.items()) + "}")), max_leaves=12)


def scalar_text(value) -> str:
    if isinstance(value, bool):
        return str(value).lower()
    if isinstance(value, float):
        return {"nan": "nan", "inf": "inf", "-inf": "-inf"}.get(repr(value), repr(value))
    if isinstance(value, str):
        return '"' + value.encode("unicode_escape").decode().replace('"', '\\"') + '"'
    return str(value)


values = toml_value(toml_scalars.map(scalar_text))
KEYS = ["name", "convention", "length_unit", "angle_unit", "alpha", "a", "d", "theta", "type", "limits",
        "max_velocity", "max_acceleration", "axis", "point", "xyz", "rpy", "matrix", "description", "x"]


@st.composite
def toml_documents(draw):
    """Documents shaped like robot files, with random keys and values in random places."""
    lines = [f"{key} = {draw(values)}" for key in draw(st.lists(st.sampled_from(KEYS[:4] + ["x"]), max_size=5,
                                                                 unique=True))]
    for header in draw(st.lists(st.sampled_from(["[[joints]]", "[[tool]]", "[[base]]", "[tool]", "[base]"]),
                                max_size=5)):
        lines.append(header)
        lines += [f"{key} = {draw(values)}" for key in draw(st.lists(st.sampled_from(KEYS), max_size=6,
                                                                     unique=True))]
    return "\n".join(lines) + "\n"


@FUZZ
@given(toml_documents())
def test_random_toml_documents_load_or_get_armkit_errors(tmp_path, document):
    check_loads_or_refuses(tmp_path, document.encode())


NUMBER = re.compile(r"(?<== )-?[0-9][0-9.e+-]*|(?<=\[)-?[0-9.]+|(?<=, )-?[0-9.]+")


@st.composite
def mutated_shipped_files(draw):
    """A shipped robot file with values swapped for random TOML values, lines dropped or duplicated,
    or bytes flipped."""
    text = SHIPPED[draw(st.sampled_from(sorted(SHIPPED)))]
    for _ in range(draw(st.integers(1, 4))):
        kind = draw(st.sampled_from(["value", "number", "drop", "duplicate", "byte"]))
        lines = text.splitlines()
        i = draw(st.integers(0, len(lines) - 1))
        if kind == "value" and " = " in lines[i]:
            lines[i] = lines[i].split(" = ")[0] + " = " + draw(values)
        elif kind == "number":
            spots = list(NUMBER.finditer(text))
            if spots:
                m = draw(st.sampled_from(spots))
                swap = draw(st.sampled_from(["1e308", "-1e308", "0", "nan", "inf", "1e-320", "1e6", "-0.0",
                                             '"1"', "[1]"]))
                text = text[:m.start()] + swap + text[m.end():]
                continue
        elif kind == "drop":
            del lines[i]
        elif kind == "duplicate":
            lines.insert(i, lines[i])
        else:
            data = bytearray(text.encode())
            data[draw(st.integers(0, len(data) - 1))] = draw(st.integers(0, 255))
            return bytes(data)
        text = "\n".join(lines) + "\n"
    return text.encode()


@FUZZ
@given(mutated_shipped_files())
def test_mutated_shipped_files_load_or_get_armkit_errors(tmp_path, data):
    check_loads_or_refuses(tmp_path, data)
