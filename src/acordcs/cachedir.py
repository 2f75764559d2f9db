"""Where analysed grammars are kept: a private per-user directory, or nowhere.

lark's ``cache=True`` writes a pickle to a predictable name in the shared temp directory and loads
whatever it finds there, so anyone able to write to /tmp could run code as our user. The cache goes to
``$XDG_CACHE_HOME/acordcs`` (default ``~/.cache/acordcs``), created with mode 0700 and used only while
it belongs to us and nobody else can write to it; otherwise grammars are analysed afresh (slower
start-up, same results). It serves the FCL reader and the rule language's lark parser.

A cache file is named by what lark's own check of it covers (lark's and Python's versions, the
grammar): a file made by another Python is never read, so two Pythons sharing the directory do not
take turns rewriting one file. lark rewrites in place a file it cannot load (truncated, corrupt):
it builds the grammar afresh, as when there is no file.
"""

from __future__ import annotations

import os
import stat
import sys


def private_dir() -> str | None:
    """The private cache directory, or None when it cannot be made or is not safely ours."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    path = os.path.join(base, "acordcs")
    try:
        os.makedirs(path, mode=0o700, exist_ok=True)
        info = os.lstat(path)
    except OSError:
        return None
    if not stat.S_ISDIR(info.st_mode) or info.st_uid != os.getuid() or info.st_mode & 0o022:
        return None
    return path


def lark_cache(grammar: str, name: str) -> str | bool:
    """The ``cache`` argument for ``Lark(...)``: a file in the private directory, or False."""
    directory = private_dir()
    if directory is None:
        return False
    import hashlib  # here: only lark's cache needs it, and it costs every `validate` 3 ms

    import lark

    python = f"{sys.implementation.name}{sys.version_info[0]}.{sys.version_info[1]}"
    key = f"{lark.__version__}\0{python}\0{name}\0{grammar}"
    digest = hashlib.sha256(key.encode()).hexdigest()[:32]
    path = os.path.join(directory, f"{name}-{digest}.lark-cache")
    try:
        info = os.lstat(path)
    except FileNotFoundError:
        return path
    except OSError:
        return False
    if not stat.S_ISREG(info.st_mode) or info.st_uid != os.getuid() or info.st_mode & 0o022:
        return False  # not ours, or writable by others: never unpickle it
    return path
