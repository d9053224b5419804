"""The trust rule of shared caches, on real files, links, FIFOs and another user's folders:
which paths may be executed or unpickled, and which private folder a process may use."""

import os
import stat
import threading

import pytest

from stability.util.trust import (TrustRule, UntrustedPath, chain_problem,
                                  private_folder_problem, read_trusted)

NOBODY = 65534
needs_root = pytest.mark.skipif(os.geteuid() != 0, reason="giving a file away needs root")


@pytest.fixture
def tree(tmp_path):
    """A cache root with a folder and a file, all this user's, mode 0755 and 0644."""
    root = tmp_path / "root"
    (root / "loops").mkdir(parents=True, mode=0o755)
    os.chmod(root, 0o755)
    (root / "loops" / "entry").write_bytes(b"machine code")
    os.chmod(root / "loops" / "entry", 0o644)
    return root


def test_a_tree_of_this_users_own_closed_to_others_is_trusted(tree):
    rule = TrustRule.from_environment({})
    assert chain_problem(tree, tree / "loops" / "entry", rule) is None
    assert read_trusted(tree / "loops" / "entry", rule) == b"machine code"


@pytest.mark.parametrize("where", ["root", "loops", "entry"])
@pytest.mark.parametrize("bits, words", [(stat.S_IWGRP, "writable by its group"),
                                         (stat.S_IWOTH, "writable by every user")])
def test_a_component_others_may_write_is_named_with_the_reason(tree, where, bits, words):
    path = {"root": tree, "loops": tree / "loops", "entry": tree / "loops" / "entry"}[where]
    os.chmod(path, path.stat().st_mode & 0o777 | bits)
    why = chain_problem(tree, tree / "loops" / "entry", TrustRule.from_environment({}))
    assert why is not None and why.startswith(f"{path} ") and words in why


def test_a_group_named_for_the_cache_may_write_it(tree):
    gid = os.getgid()
    os.chmod(tree / "loops", 0o775)
    os.chmod(tree / "loops" / "entry", 0o664)
    assert chain_problem(tree, tree / "loops" / "entry", TrustRule.from_environment({})) \
        is not None
    rule = TrustRule.from_environment({"STABILITY_CACHE_GROUP": str(gid)})
    assert chain_problem(tree, tree / "loops" / "entry", rule) is None
    assert read_trusted(tree / "loops" / "entry", rule) == b"machine code"


@needs_root
def test_another_users_file_is_trusted_only_when_the_user_names_them(tree):
    os.chown(tree / "loops", NOBODY, NOBODY)
    why = chain_problem(tree, tree / "loops" / "entry", TrustRule.from_environment({}))
    assert why is not None and str(tree / "loops") in why and "does not trust" in why
    named = TrustRule.from_environment({"STABILITY_CACHE_OWNER": f"nobody, {NOBODY}"})
    assert chain_problem(tree, tree / "loops" / "entry", named) is None


def test_a_link_anywhere_below_the_root_is_refused(tree, tmp_path):
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir(mode=0o755)
    (elsewhere / "entry").write_bytes(b"planted")
    os.chmod(elsewhere / "entry", 0o644)
    (tree / "loops" / "entry").unlink()
    (tree / "loops" / "entry").symlink_to(elsewhere / "entry")
    rule = TrustRule.from_environment({})
    assert "symbolic link" in chain_problem(tree, tree / "loops" / "entry", rule)
    with pytest.raises(UntrustedPath, match="symbolic link"):
        read_trusted(tree / "loops" / "entry", rule)
    os.rename(tree / "loops", tmp_path / "real-loops")
    (tree / "loops").symlink_to(tmp_path / "real-loops")
    assert chain_problem(tree, tree / "loops" / "x", rule) == f"{tree / 'loops'} is a symbolic link"


def test_a_fifo_or_a_hard_link_in_place_of_a_file_is_refused_without_waiting(tree, tmp_path):
    fifo = tree / "loops" / "fifo"
    os.mkfifo(fifo, 0o644)
    outcome = []
    reader = threading.Thread(target=lambda: outcome.append(_refusal(fifo)), daemon=True)
    reader.start()
    reader.join(timeout=10)
    assert outcome and "neither a folder nor a regular file" in outcome[0]
    os.link(tree / "loops" / "entry", tmp_path / "second-name")
    assert "2 hard links" in _refusal(tree / "loops" / "entry")


def _refusal(path) -> str:
    try:
        read_trusted(path, TrustRule.from_environment({}))
    except UntrustedPath as exc:
        return str(exc)
    return "read"


def test_a_missing_component_ends_the_walk_as_trusted(tree):
    assert chain_problem(tree, tree / "loops" / "__pycache__" / "x.nbi",
                         TrustRule.from_environment({})) is None


def test_a_private_folder_is_a_real_folder_of_this_users_closed_to_all_others(tmp_path):
    mine = tmp_path / "mine"
    mine.mkdir(mode=0o700)
    assert private_folder_problem(mine) is None
    os.chmod(mine, 0o750)
    assert "open to other users (mode 0750)" in private_folder_problem(mine)
    link = tmp_path / "link"
    link.symlink_to(mine)
    assert private_folder_problem(link) == f"{link} is a symbolic link"
    afile = tmp_path / "file"
    afile.write_text("")
    assert private_folder_problem(afile) == f"{afile} is not a folder"


@needs_root
def test_another_users_folder_is_no_private_folder(tmp_path):
    theirs = tmp_path / "theirs"
    theirs.mkdir(mode=0o700)
    os.chown(theirs, NOBODY, NOBODY)
    assert private_folder_problem(theirs) == f"{theirs} belongs to user nobody"


def test_a_name_that_is_no_user_or_group_trusts_no_one_more():
    rule = TrustRule.from_environment({"STABILITY_CACHE_OWNER": "no-such-user-here",
                                       "STABILITY_CACHE_GROUP": "no-such-group-here"})
    assert rule == TrustRule(frozenset({os.getuid(), 0}), None)
