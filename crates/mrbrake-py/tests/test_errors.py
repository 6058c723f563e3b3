"""Errors by kind: bad input is a ValueError with the CLI's message; numerical failure a
mrbrake.SolverError."""

import pytest

import mrbrake

BAD_SPEC = """
name = "bad"
configuration = "single-disc"
[materials]
flux_path = "steel-1008"
non_magnetic = "aluminium"
shaft = "stainless-304"
fluid = "mrf-122eg"
[shaft]
radius = "5mm"
[housing]
outer_radius = "42mm"
case_thickness = "4mm"
end_plate_thickness = "5mm"
inner_case_thickness = "5mm"
[disc]
inner_radius = "22.5mm"
outer_radius = "20mm"
thickness = "1mm"
gap = "-0.5mm"
count = 1
[coil]
placement = "outer"
window_width = "8mm"
window_height = "10mm"
bobbin_wall = "0.5mm"
wire = { awg = 24 }
max_current = "2A"
[envelope]
diameter = "90mm"
length = "40mm"
"""


def test_solver_error_is_a_runtime_error():
    assert issubclass(mrbrake.SolverError, RuntimeError)
    assert mrbrake.SolverError.__module__ == "mrbrake"


def test_missing_spec_file_has_the_cli_message(cli, tmp_path):
    missing = tmp_path / "no-such-spec.toml"
    code, message = cli.fail("analyze", missing)
    assert code == 2
    # A missing file is FileNotFoundError (an OSError), with the CLI's message (issue 27).
    with pytest.raises(FileNotFoundError) as e:
        mrbrake.analyze(str(missing))
    assert str(e.value) == message


def test_invalid_spec_fields_have_the_cli_message(cli, tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(BAD_SPEC)
    code, message = cli.fail("analyze", path)
    assert code == 2
    with pytest.raises(ValueError) as e:
        mrbrake.analyze(path)  # os.PathLike
    assert str(e.value) == message
    assert "gap" in message and "outer_radius" in message


def test_bad_arguments_are_value_errors(cli):
    code, message = cli.fail("analyze", "--mesh", "bogus")
    with pytest.raises(ValueError) as e:
        mrbrake.analyze(mesh="bogus")
    # The same field error, named by the CLI's flag and by the keyword argument.
    assert message == f"--{e.value}" and str(e.value).startswith("mesh: ")
    assert "coarse, default, fine" in message
    with pytest.raises(ValueError, match=r"^currents: .*got 1; allowed: >= 2"):
        mrbrake.analyze(currents=1)
    for kwargs in [dict(order=3), dict(currents=1), dict(speed="5 parsecs"), dict(spec=42)]:
        with pytest.raises(ValueError):
            mrbrake.analyze(**kwargs)


def test_unknown_material_has_the_cli_message(cli):
    code, message = cli.fail("materials", "show", "unobtainium")
    assert code == 2
    with pytest.raises(ValueError) as e:
        mrbrake.materials.get("unobtainium")
    assert str(e.value) == message


def test_an_unfittable_characterisation_is_a_solver_or_value_error():
    # A constant current has no ramps to segment: the library says which kind this is.
    t = [i * 1e-3 for i in range(100)]
    with pytest.raises(ValueError):
        mrbrake.sysid.characterize(t, [1.0] * 100, [0.5] * 100)


def test_an_all_zero_response_is_an_input_error_with_the_cli_message(cli, tmp_path):
    # A response that is zero everywhere has nothing to fit: refused as input (issue 18: it used to
    # reach the least-squares problem and fail there as a numerical error).
    omega = [10 ** (k / 10) for k in range(20)]
    path = tmp_path / "frd.csv"
    path.write_text("omega_rad_s,re,im\n" + "".join(f"{w!r},0,0\n" for w in omega))
    code, message = cli.fail("tfest", path, "--poles", "2")
    assert code == 2
    with pytest.raises(ValueError) as e:
        mrbrake.sysid.tfest(omega, [0j] * len(omega), poles=2)
    # The CLI names the file in front of the library's message.
    assert message == f"{path}: {e.value}"
    assert "every response is zero" in message
