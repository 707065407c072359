"""The tools' reader of the FMU's parameter sets and experiments (plateimpact_tools.references):
every SSP value type as its Python type, the refusals by name, the scenes found through the
manifest, and an experiment run through it that meets its reference result."""

import pytest
from fmpy import read_model_description, simulate_fmu

from conftest import SCENES
from plateimpact_tools import references
from test_reference import assert_matches

HEAD = (
    '<?xml version="1.0" encoding="UTF-8"?>\n<ssv:ParameterSet '
    'xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" '
    'name="t">\n  <ssv:Parameters>\n'
)
TAIL = "  </ssv:Parameters>\n</ssv:ParameterSet>\n"


def ssv(*parameters):
    """The bytes of an SSV file of (name, type, value text) parameters."""
    return (
        HEAD
        + "".join(
            f'    <ssv:Parameter name="{n}"><ssv:{t} value="{v}"/></ssv:Parameter>\n'
            for n, t, v in parameters
        )
        + TAIL
    ).encode()


def test_every_value_type_is_read_as_its_python_type():
    values = references.read_ssv(
        ssv(
            ("a", "Real", "5.913e-05"),
            ("b", "Integer", "14"),
            ("c", "Boolean", "false"),
            ("d", "String", "x &amp; y"),
        )
    )
    assert values == {"a": 5.913e-05, "b": 14, "c": False, "d": "x & y"}
    assert [type(v) for v in values.values()] == [float, int, bool, str]


@pytest.mark.parametrize(
    "parameter, words",
    [
        (("e", "Enumeration", "1"), "parameter e: the value type Enumeration"),
        (("b", "Boolean", "yes"), "parameter b: 'yes' is no Boolean"),
        (("i", "Integer", "1.5"), "parameter i: '1.5' is no Integer"),
    ],
)
def test_a_value_it_cannot_type_is_refused_by_name(parameter, words):
    with pytest.raises(ValueError, match=words):
        references.read_ssv(ssv(parameter))


def test_a_parameter_set_twice_is_refused():
    with pytest.raises(ValueError, match="parameter a is set twice"):
        references.read_ssv(ssv(("a", "Real", "1"), ("a", "Real", "2")))


@pytest.mark.parametrize("fmi", [2, 3])
def test_each_shipped_set_gives_every_parameter_its_type(fmi, fmu_path, fmu3_path):
    """Through the manifest, every scene of scenes/ is there, and each of its parameters comes
    back with the Python type of its variable: the String parameters as text."""
    fmu = fmu_path if fmi == 2 else fmu3_path
    assert references.scenes(fmu) == sorted(p.stem for p in SCENES.glob("*.json"))
    kinds = {
        "Real": float,
        "Float64": float,
        "Integer": int,
        "Int32": int,
        "Boolean": bool,
        "String": str,
    }
    parameters = {
        v.name: v for v in read_model_description(fmu).modelVariables if v.causality == "parameter"
    }
    assert any(v.type == "String" for v in parameters.values())
    for scene in references.scenes(fmu):
        values = references.parameter_set(fmu, scene)
        assert set(values) == set(parameters), scene
        for name, value in values.items():
            assert type(value) is kinds[parameters[name].type], (scene, name, value)


def test_an_unknown_scene_is_refused_naming_those_there(fmu_path):
    with pytest.raises(
        KeyError, match="carries no experiment 'forced-99hz'; it carries clamped-panel, energy,"
    ):
        references.parameter_set(fmu_path, "forced-99hz")


def test_an_experiment_run_through_the_tools_meets_its_reference(fmu3_path):
    """simulate_fmu(fmu, **experiment(...)) is the experiment (horizon, step, every parameter):
    its rows meet the reference result under test_reference's tolerances."""
    scene = "energy"
    run = references.experiment(fmu3_path, scene)
    assert (run["start_time"], run["stop_time"], run["output_interval"]) == (0.0, 1.0, 1e-3)
    expected = references.reference(fmu3_path, scene)
    result = simulate_fmu(fmu3_path, **run, output=list(expected.dtype.names[1:]))
    assert_matches(result, expected, scene)


def test_a_file_is_read_by_its_path(tmp_path):
    path = tmp_path / "set.ssv"
    path.write_bytes(ssv(("plate.clamp", "String", "xmin")))
    assert references.read_ssv(path) == references.read_ssv(str(path)) == {"plate.clamp": "xmin"}
