"""A file the build reads back from the output directory is read only when it is a regular file of
at most 64 MiB: a FIFO where the package's ``descriptor.xml`` (or any generated file, or the
manifest) was is reported at once, never waited on; a 1 GiB sparse one is not read either. Both
are taken as edited files: moved aside unread to ``.edited`` (no copy) and the file regenerated;
``--check`` says so and exits 1."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from acordcs.generator.paths import READ_LIMIT, Unreadable, read_bounded
from tests.support.generator import build
from tests.support.toolchain import WEBLAB, entry_point

DESCRIPTOR = "weblab_app/descriptor.xml"


def _timed(*args: str, timeout: float = 120) -> tuple[subprocess.CompletedProcess, float]:
    start = time.monotonic()
    done = subprocess.run(
        [*entry_point(), *args], capture_output=True, text=True, timeout=timeout, check=False
    )
    return done, time.monotonic() - start


@pytest.fixture
def built(tmp_path: Path) -> Path:
    out = tmp_path / "out"
    assert build(WEBLAB, out, "-q").code == 0
    return out


def test_read_bounded_refuses_at_once_what_is_not_a_small_regular_file(tmp_path: Path):
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    start = time.monotonic()
    with pytest.raises(Unreadable, match="named pipe"):
        read_bounded(fifo)  # no writer: an open without O_NONBLOCK would wait for one
    assert time.monotonic() - start < 1
    big = tmp_path / "big"
    with open(big, "wb") as handle:
        handle.truncate(READ_LIMIT + 1)
    with pytest.raises(Unreadable, match="larger than 64 MiB"):
        read_bounded(big)
    (tmp_path / "link").symlink_to(big)
    with pytest.raises(Unreadable, match="symbolic link"):
        read_bounded(tmp_path / "link")
    with pytest.raises(Unreadable, match="directory"):
        read_bounded(tmp_path)
    with pytest.raises(FileNotFoundError):
        read_bounded(tmp_path / "missing")
    (tmp_path / "small").write_bytes(b"abc")
    assert read_bounded(tmp_path / "small") == b"abc"


def test_a_fifo_descriptor_is_reported_not_waited_on(built: Path):
    # a FIFO nobody writes to blocks its reader for ever: a build that tried to read it would
    # run into the 60 s timeout, whatever the host's load (a bound relative to a plain build
    # failed on a loaded host, the writing build being slower than a check)
    (built / DESCRIPTOR).unlink()
    os.mkfifo(built / DESCRIPTOR)
    for args in (("--check",), ("--check", "--strict"), ()):
        done, _took = _timed("build", str(WEBLAB), "-o", str(built), *args, timeout=60)
        assert "named pipe (FIFO)" in done.stderr, done.stderr
        if args:
            assert done.returncode == 1, done.stderr
            assert "not up to date" in done.stderr
    assert done.returncode == 0, done.stdout + done.stderr
    assert (built / DESCRIPTOR).is_file() and not (built / DESCRIPTOR).is_symlink()
    assert (built / f"{DESCRIPTOR}.edited").is_fifo()  # moved aside, never opened for reading
    again, _ = _timed("build", str(WEBLAB), "-o", str(built), "--check")
    assert again.returncode == 0, again.stderr


def test_a_huge_sparse_descriptor_is_moved_aside_unread(built: Path):
    path = built / DESCRIPTOR
    with open(path, "r+b") as handle:
        handle.truncate(1024**3)
    inode = path.stat().st_ino
    done, _ = _timed("build", str(WEBLAB), "-o", str(built), "--check")
    assert done.returncode == 1 and "larger than 64 MiB" in done.stderr, done.stderr
    done, _ = _timed("build", str(WEBLAB), "-o", str(built))
    assert done.returncode == 0, done.stderr
    assert "moved aside unread" in done.stderr
    edited = built / f"{DESCRIPTOR}.edited"
    assert edited.stat().st_ino == inode and edited.stat().st_size == 1024**3  # renamed: no copy
    assert path.stat().st_size < READ_LIMIT


def test_a_fifo_manifest_is_not_waited_on(built: Path):
    manifest = built / ".acordcs-manifest.json"
    manifest.unlink()
    os.mkfifo(manifest)
    done, _ = _timed("build", str(WEBLAB), "-o", str(built), "--check", timeout=60)
    assert done.returncode == 1 and "named pipe" in done.stderr, done.stderr


def test_a_fifo_user_class_is_reported_by_strict(built: Path):
    cls = built / "weblab_app" / "components" / "Vision.py"
    cls.unlink()
    os.mkfifo(cls)
    done, _ = _timed("build", str(WEBLAB), "-o", str(built), "--check", "--strict", timeout=60)
    assert done.returncode == 1, done.stdout + done.stderr
    assert "G705" in done.stdout and "named pipe" in done.stdout
    assert cls.is_fifo()  # the user's: left as it is


if sys.platform != "linux":  # mkfifo and sparse files as Linux has them
    pytestmark = pytest.mark.skip(reason="Linux only")
