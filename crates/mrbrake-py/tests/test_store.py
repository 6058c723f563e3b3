"""A sweep's store (written by the CLI) read back by mrbrake.store: the same records as
`mrbrake export --json`, as a table."""

import math

import pytest

import mrbrake


@pytest.fixture(scope="module")
def swept_store(cli, tmp_path_factory):
    path = tmp_path_factory.mktemp("store") / "sweep.sqlite"
    cli.json("sweep", "examples/specs/single-disc.toml", "--vary", "g=0.5mm,0.75mm", "--mesh",
             "coarse", "--store", path)
    return path


def test_records_equal_the_cli_export(cli, swept_store):
    expected = cli.json("export", swept_store)
    assert mrbrake.store.records(swept_store) == expected
    assert len(expected) == 2


def test_load_gives_one_row_per_design(swept_store):
    table = mrbrake.store.load(swept_store)
    rows = table.to_dict("records") if hasattr(table, "to_dict") else table
    assert len(rows) == 2
    records = {r["key"]: r for r in mrbrake.store.records(swept_store)}
    for row in rows:
        record = records[row["key"]]
        assert row["status"] == record["status"]
        for name, value in record["metrics"].items():
            if isinstance(value, float):
                assert row[name] == value
        gap = next(v for k, v in record["variables"].items())
        assert math.isfinite(gap)


def test_a_missing_store_is_an_input_error(tmp_path, cli):
    missing = tmp_path / "none.sqlite"
    code, message = cli.fail("export", missing, "--json")
    with pytest.raises(ValueError) as e:
        mrbrake.store.records(missing)
    assert str(e.value) == message
