"""Loading a study file (stability.study.load): the kind named at the top, the file read whole
or refused in one line, the overrides (--set, --members, --quick) applied and named in the
message of a problem they make."""

import pytest

from stability.cli import main
from stability.study import ConfigError, load_study
from stability.study.load import MAX_STUDY_BYTES, parse, read, set_value

from .test_config import TENNIS, write_study


@pytest.mark.parametrize(
    "text, words",
    [
        ('study = "tennis"\n', ['study must be one of', '"tennis_racket"', '"tennis"']),
        ('title = "no kind"\n', ["missing key 'study'"]),
        ('study = "tennis_racket\n', ["not valid TOML", "line 1"]),
        ('study = "tennis_racket"\nflavour = 1\n', ["unknown top-level key 'flavour'"]),
    ],
)
def test_bad_top_level(text, words, tmp_path, capsys):
    path = tmp_path / "x.toml"
    path.write_text(text)
    assert main(["run", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith(f"{path}: ")
    for word in words:
        assert word in err


def test_missing_file_and_bad_override(tmp_path, capsys):
    assert main(["run", str(tmp_path / "none.toml")]) == 2
    assert capsys.readouterr().err.strip() == f"{tmp_path / 'none.toml'}: no such file"
    path, out = write_study(tmp_path, "")
    assert main(["run", str(path), "--set", "ensemble.members=0"]) == 2
    err = capsys.readouterr().err.strip()
    assert "(--set ensemble.members)" in err and "members must be an integer >= 1, got 0" in err
    assert main(["run", str(path), "--members", "-3"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "--members" in err
    assert not out.exists()


def test_quick_mode_and_overrides_take_effect():
    kind, config, _ = load_study(
        TENNIS, quick=True, overrides=[("ensemble.epsilon", "1e-5"), ("integration.method", "lp2")],
        members=77,
    )
    assert config["ensemble"] == {"members": 77, "epsilon": 1e-5, "seed": 1}
    assert config["integration"]["method"] == "lp2"
    assert config["integration"]["t_end"] == kind.quick["integration"]["t_end"]


def test_set_value_reads_a_toml_value_or_else_a_bare_word():
    raw = {"ensemble": {"members": 5}}
    for text, value in (("7", 7), ("1e-4", 1e-4), ('"lp2"', "lp2"), ("lp2", "lp2"),
                        ("[1, 2, 3]", [1, 2, 3]), ("true", True)):
        set_value(raw, "integration.method", text)
        assert raw["integration"]["method"] == value
    assert raw["ensemble"] == {"members": 5}
    with pytest.raises(ConfigError, match="must name a section and a key"):
        set_value(raw, "members", "5")
    with pytest.raises(ConfigError, match=r"--set: \[title\] is not a section"):
        set_value({"title": "x"}, "title.name", "5")


def test_read_refuses_a_folder_a_large_file_and_bad_toml_in_one_line(tmp_path):
    with pytest.raises(ConfigError, match="is a folder, not a study file"):
        read(tmp_path)
    large = tmp_path / "large.toml"
    large.write_bytes(b"#" * (MAX_STUDY_BYTES + 1))
    with pytest.raises(ConfigError, match="larger than the 1 MiB a study file may have"):
        read(large)
    with pytest.raises(ConfigError, match=r"^f.toml: not valid TOML"):
        parse("study = ", "f.toml")
    assert parse("\ufeffstudy = 'bat'") == {"study": "bat"}


def test_a_dispersions_section_where_the_kind_draws_none_names_the_kinds_that_do(tmp_path):
    path = tmp_path / "x.toml"
    path.write_text('study = "tennis_racket"\n[dispersions]\nrate = {relative = 0.1}\n')
    with pytest.raises(ConfigError, match="study 'tennis_racket' draws no dispersions; the "
                                          "studies that take .dispersions. .* are "):
        load_study(path)
