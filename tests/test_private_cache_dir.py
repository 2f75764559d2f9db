"""lark's analysed grammars are cached only where nobody else can plant a pickle."""

from __future__ import annotations

import os

from acordcs.cachedir import lark_cache


def test_cache_goes_to_a_private_directory(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    path = lark_cache("start: NAME", "demo")
    assert isinstance(path, str) and path.startswith(str(tmp_path / "acordcs"))
    assert os.stat(tmp_path / "acordcs").st_mode & 0o777 == 0o700


def test_a_directory_others_can_write_to_is_not_used(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    (tmp_path / "acordcs").mkdir(mode=0o777)
    os.chmod(tmp_path / "acordcs", 0o777)
    assert lark_cache("start: NAME", "demo") is False


def test_a_cache_file_others_can_write_to_is_never_loaded(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    path = lark_cache("start: NAME", "demo")
    with open(path, "wb") as planted:
        planted.write(b"not a pickle lark wrote")
    os.chmod(path, 0o666)
    assert lark_cache("start: NAME", "demo") is False


def test_the_cache_name_changes_with_the_grammar(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert lark_cache("start: NAME", "demo") != lark_cache("start: NUMBER", "demo")
