"""`mrbrake.response` against `mrbrake response --json`: the same inputs give the same document,
and bad input is the CLI's error as a ValueError."""

import mrbrake


def test_response_matches_the_cli(cli):
    report = mrbrake.response(mesh="coarse", duration="5ms", step="0A..1A", bias=0.5)
    expected = cli.json("response", "--mesh", "coarse", "--duration", "5ms", "--step", "0A..1A",
                        "--bias", "0.5A")
    for key in ("step", "frequency_response", "bandwidth_rad_s", "dc_gain_Nm_per_A", "bias_A",
                "direction_2"):
        assert report[key] == expected[key], key
    assert report["bandwidth_rad_s"] > 0


def test_response_bad_bias_is_value_error(cli):
    code, message = cli.fail("response", "--mesh", "coarse", "--bias", "0A")
    try:
        mrbrake.response(mesh="coarse", bias=0.0)
    except ValueError as e:
        assert code == 2 and str(e) in message, (str(e), message)
    else:
        raise AssertionError("a zero bias must be a ValueError")
