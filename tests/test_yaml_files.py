"""Reading a user's YAML or JSON file (redkin._yaml_files): numbers as JSON and YAML 1.2 write them."""

import json

import numpy as np
import pytest
import yaml
from hypothesis import example, given, settings
from hypothesis import strategies as st

from redkin._yaml_files import read_yaml
from redkin.errors import RobotDescriptionError


@settings(max_examples=60, deadline=None)
@given(values=st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=1, max_size=8), as_json=st.booleans())
@example(values=[1e-9, 5e-5, -2.5e300, 1e16], as_json=True)  # json.dumps writes "1e-09": no dot, YAML 1.1's string
def test_every_number_written_by_json_or_yaml_reads_back_as_the_same_float(tmp_path_factory, values, as_json):
    path = tmp_path_factory.mktemp("numbers") / ("data.json" if as_json else "data.yaml")
    data = {"margin": values[0], "values": values}
    path.write_text(json.dumps(data) if as_json else yaml.safe_dump(data))
    read = read_yaml(path, "test file")
    assert read == data and all(isinstance(v, float) for v in read["values"])


@pytest.mark.parametrize(("text", "value"), [
    ("1e-3", 1e-3), ("5E3", 5e3), ("-2.5e+2", -250.0), (".5", 0.5), ("1.", 1.0), ("+1e0", 1.0), ("-.inf", -np.inf),
    ("3", 3), ("-7", -7), ('"1e-3"', "1e-3"), ("1e", "1e"), ("e5", "e5"), ("1.2.3", "1.2.3"),
])
def test_hand_written_numbers_are_read_as_yaml_1_2_reads_them(tmp_path, text, value):
    path = tmp_path / "hand.yaml"
    path.write_text(f"x: {text}\n")
    read = read_yaml(path, "test file")["x"]
    assert read == value and type(read) is type(value)


def test_a_file_that_is_not_yaml_names_the_file_and_line(tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text("a: 1\nb: [1, 2\n")
    with pytest.raises(RobotDescriptionError, match=r"bad\.yaml'?: not YAML or JSON at line \d"):
        read_yaml(path, "test file")
