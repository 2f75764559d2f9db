"""Certificates made for a test with openssl: a CA of the test's own and a server certificate it
signs, for a name or an address the test gives (never the machine's own CAs)."""

from __future__ import annotations

import subprocess
from dataclasses import dataclass
from pathlib import Path


def openssl(*args: str, cwd: Path) -> None:
    subprocess.run(["openssl", *args], cwd=cwd, check=True, capture_output=True, timeout=60)


@dataclass(frozen=True)
class ServerCertificate:
    ca: Path  # the CA's certificate (PEM): what a client verifies the server against
    certificate: Path
    key: Path


def make_server_certificate(
    directory: Path, *, san: str = "IP:127.0.0.1", name: str = "server"
) -> ServerCertificate:
    """In ``directory``: ``ca.pem`` (a CA made here; one directory per CA) and
    ``<name>.pem``/``<name>.key``, a certificate it signs for ``san`` (openssl's
    subjectAltName, e.g. ``IP:127.0.0.1``)."""
    directory.mkdir(parents=True, exist_ok=True)
    ca, ca_key = "ca.pem", "ca.key"
    openssl("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "2",
            "-subj", f"/CN={directory.name}-ca", "-keyout", ca_key, "-out", ca, cwd=directory)  # fmt: skip
    (directory / f"{name}.ext").write_text(f"subjectAltName={san}\n")
    openssl("req", "-newkey", "rsa:2048", "-nodes", "-subj", f"/CN={name}",
            "-keyout", f"{name}.key", "-out", f"{name}.csr", cwd=directory)  # fmt: skip
    openssl("x509", "-req", "-in", f"{name}.csr", "-CA", ca, "-CAkey", ca_key,
            "-CAcreateserial", "-days", "2", "-extfile", f"{name}.ext", "-out", f"{name}.pem",
            cwd=directory)  # fmt: skip
    return ServerCertificate(directory / ca, directory / f"{name}.pem", directory / f"{name}.key")
