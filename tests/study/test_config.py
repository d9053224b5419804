"""The schema of study files (stability.study.config): validation, one-line errors with exit
status 2, the resolved configuration."""

import tomllib
from pathlib import Path

import pytest

from stability.cli import main
from stability.study import STUDIES, ConfigError, Key, load_study, resolve, to_toml
from stability.study.load import parse

ROOT = Path(__file__).resolve().parents[2]
TENNIS = ROOT / "studies" / "tennis_racket.toml"


def write_study(tmp_path, text, name="x.toml"):
    """A tennis-racket study file with ``text`` whose output folder is ``tmp_path/out``."""
    path = tmp_path / name
    out = tmp_path / "out"
    where = f'dir = "{out.as_posix()}"\n'
    if "[output]\n" in text:
        text = text.replace("[output]\n", "[output]\n" + where)
    else:
        text += "[output]\n" + where
    path.write_text('study = "tennis_racket"\n' + text)
    return path, out


# Each case: the study text after the [output] table, and words the one-line message must hold.
BAD = {
    "unknown key": (
        "[ensemble]\nmember = 5\n",
        ["[ensemble]", "unknown key 'member'", "did you mean 'members'", "allowed keys"],
    ),
    "unknown section": ("[ensembel]\nmembers = 5\n", ["unknown section [ensembel]", "[ensemble]"]),
    "wrong type": (
        '[ensemble]\nmembers = "many"\n',
        ["[ensemble] members must be an integer >= 1", '"many"', "a string"],
    ),
    "float for integer": ("[ensemble]\nmembers = 1e4\n", ["members must be an integer"]),
    "impossible value": (
        "[ensemble]\nmembers = -5\n", ["[ensemble] members must be an integer >= 1, got -5"]
    ),
    "zero step": ("[integration]\nh = 0.0\n", ["[integration] h must be a number > 0 (in s)"]),
    "epsilon above 1": ("[ensemble]\nepsilon = 2.0\n", ["epsilon must be a number > 0 and <= 1"]),
    "unknown method": (
        '[integration]\nmethod = "euler"\n', ['method must be one of "rk4"', '"lp2"', '"euler"']
    ),
    "unknown scene": (
        '[integration]\nscene = "heavy_top"\n',
        ['scene must be one of "free_body", "free_body_attitude"', '"heavy_top"'],
    ),
    "method without attitude": (
        '[integration]\nscene = "free_body_attitude"\nmethod = "exact"\n',
        ["[integration] method must carry the attitude", "rk4", "'exact'"],
    ),
    "attitude on the gpu": (
        '[integration]\nscene = "free_body_attitude"\n[run]\ndevice = "gpu"\n',
        ["[run] device must be 'cpu' with scene = 'free_body_attitude'"],
    ),
    "unknown preset": ('[body]\npreset = "bat"\n', ['preset must be one of', '"tennis_racket"']),
    "axis out of range": ("[spin]\naxis = 4\n", ["axis must be one of 1, 2, 3", "got 4"]),
    "short moments": ("[body]\nmoments = [1.0, 2.0]\n", ["moments must be a list of 3 numbers"]),
    "preset and moments": (
        '[body]\npreset = "phone"\nmoments = [1.0, 2.0, 3.0]\n',
        ["[body] give only one of preset, moments"],
    ),
    "unphysical moments": (
        "[body]\nmoments = [1.0, 2.0, 4.0]\n", ["[body]", "triangle inequality"]
    ),
    "t_end not whole steps": (
        "[integration]\nt_end = 10.001\n", ["[integration] t_end must be a whole number of steps"]
    ),
    "save_every not dividing": (
        "[integration]\nsave_every = 7\n", ["save_every must divide the number of steps"]
    ),
    "empty fit window": ("[analysis]\nfit_below = 1e-4\n", ["fit_below must be >", "empty"]),
    "bad figure format": ('[output]\nformats = ["gif"]\n', ["formats must be a list of values"]),
    "unknown compression": ('[output]\ncompression = "lz5"\n',
                            ['compression must be one of "zlib", "zstd", "none"', '"lz5"']),
    "dataset not netCDF": ('[output]\ndataset = "run.csv"\n',
                           ['[output] dataset must be a string ending in .nc, got "run.csv"']),
    "section as value": ("ensemble = 5\n", ["[ensemble] must be a section"]),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_study_file_is_one_line_exit_2_and_writes_nothing(case, tmp_path, capsys):
    text, words = BAD[case]
    path, out = write_study(tmp_path, text)
    assert main(["run", str(path)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith(f"{path}: ")
    for word in words:
        assert word in lines[0], (word, lines[0])
    assert "Traceback" not in captured.err
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.toml"]


def test_resolved_config_fills_defaults_and_round_trips_as_toml(tmp_path):
    kind, config, _ = load_study(TENNIS)
    schema = kind.schema
    for section in schema.sections:
        for key in section.keys:
            group = [g for g in section.exclusive if key.name in g]
            if key.default is None or (group and key.name != group[0][0]):
                continue
            assert key.name in config[section.name], (section.name, key.name)
    assert tomllib.loads(to_toml(config)) == config
    # The shipped study file states the defaults: it resolves to what an empty file does.
    bare = tmp_path / "bare.toml"
    bare.write_text('study = "tennis_racket"\n')
    assert load_study(bare)[1] == config


def test_moments_replace_the_preset(tmp_path):
    path, _ = write_study(tmp_path, '[body]\nmoments = [1, 2, 2.5]\nname = "box"\n')
    _, config, _ = load_study(path)
    assert config["body"] == {"moments": [1.0, 2.0, 2.5], "physical": True, "name": "box"}


def test_key_checks_types_and_ranges():
    rate = Key("rate", "float", 1.0, "spin", unit="rad s-1", minimum=0.0, exclusive_minimum=True)
    assert rate.check(3) == 3.0 and isinstance(rate.check(3), float)
    for bad in (0.0, -1.0, True, "3", float("inf"), [1.0]):
        with pytest.raises(ValueError, match=r"a number > 0 \(in rad s-1\)"):
            rate.check(bad)
    count = Key("n", "int", 1, "count", minimum=1, maximum=10)
    assert count.check(10) == 10
    for bad in (0, 11, 2.0, False):
        with pytest.raises(ValueError, match="an integer >= 1 and <= 10"):
            count.check(bad)


def test_resolve_reports_the_first_problem_with_its_source():
    schema = STUDIES["tennis_racket"].schema
    with pytest.raises(ConfigError) as info:
        resolve(parse("[spin]\nrate = -1.0\n"), schema, "f.toml")
    assert str(info.value) == "f.toml: [spin] rate must be a number > 0 (in rad s-1), got -1.0"
    assert (info.value.section, info.value.key) == ("spin", "rate")


@pytest.mark.parametrize("overrides, title, dataset", [
    ([], "Tennis-racket flips of a perturbed spin about the intermediate axis",
     "tennis_racket.nc"),
    ([("body.preset", '"phone"')],
     "Phone flips of a perturbed spin about the intermediate axis", "phone.nc"),
    ([("body.preset", '"t_handle"'), ("spin.axis", "1")],
     "T handle flips of a perturbed spin about axis 1", "t_handle.nc"),
    ([("body.preset", '"phone"'), ("output.dataset", '"toss.nc"')],
     "Phone flips of a perturbed spin about the intermediate axis", "toss.nc"),
])
def test_the_tennis_studys_title_and_dataset_are_named_from_the_body(overrides, title, dataset):
    """A phone run of the shipped file was titled "Tennis-racket ..." in tennis_racket.nc."""
    kind, config, _ = load_study(TENNIS, overrides=overrides)
    assert (config["title"], config["output"]["dataset"]) == (title, dataset)
    assert kind.outputs(config)[0] == dataset
    assert kind.resolve(config) == config  # a resolved configuration resolves to itself
    assert tomllib.loads(to_toml(config))["title"] == title


@pytest.mark.parametrize("name, title, dataset", [
    ('name = "my box"\n', "My box flips of a perturbed spin about the intermediate axis",
     "my_box.nc"),
    ("", "Flips of a perturbed spin about the intermediate axis", "tennis_racket.nc"),
])
def test_a_body_by_moments_is_named_from_its_name(name, title, dataset, tmp_path):
    path, _ = write_study(tmp_path, f"[body]\nmoments = [1, 2, 2.5]\n{name}")
    _, config, _ = load_study(path)
    assert (config["title"], config["output"]["dataset"]) == (title, dataset)


def test_a_title_the_file_sets_is_kept(tmp_path):
    path, _ = write_study(tmp_path, 'title = "my toss"\n[body]\npreset = "phone"\n')
    _, config, _ = load_study(path)
    assert config["title"] == "my toss" and config["output"]["dataset"] == "phone.nc"


def test_a_phone_runs_checks_before_the_run_use_its_own_file_names(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "phone.nc").write_bytes(b"x")
    phone = ["run", str(TENNIS), "--set", "body.preset=phone", "--out", str(out), "--quick"]
    assert main(phone) == 2
    assert "phone.nc already exists; pass --overwrite" in capsys.readouterr().err
    assert main([*phone, "--resume"]) == 2
    err = capsys.readouterr().err
    assert "its run there is finished (phone.nc exists)" in err
    assert sorted(p.name for p in out.iterdir()) == ["phone.nc"]

