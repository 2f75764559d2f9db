"""Where a container's process keeps its context documents: in the process (``embedded``, the
default) or at an MQTT broker that containers on several machines share
(``mqtt://[USER@]HOST[:PORT][/PREFIX]``: port 1883 and topic prefix ``acordcs/ctx`` by default;
one prefix per application sharing a broker; ``mqtts://`` for TLS, port 8883 by default, the
broker's certificate verified against the CAs in ``$ACORDCS_MQTT_CA`` or else the system's), as
the launcher's ``--context`` says (default: ``$ACORDCS_CONTEXT``; docs/deployment.md).

The broker's password is read from ``$ACORDCS_MQTT_PASSWORD``, never from the command line (which
every user of the machine can read in ``ps``). With an application token (``$ACORDCS_TOKEN``, the
same in every process of the application) the documents are signed with it and only documents
signed with it are taken (:class:`~acordcs.runtime.context.mqtt.MqttContextProvider`'s
``payload_key``): another client of the broker cannot forge the application's context.

Everything that stops the connection at start is one :class:`~acordcs.runtime.errors.ConfigurationError`
naming the container, the broker's host and port, the cause and what to do, within the connect
timeout: a name that does not resolve, a broker that is not there or refuses the connection, one that
refuses the login, a peer that answers something other than MQTT (no CONNACK in time), and over
TLS a CA file that cannot be read, a certificate that does not verify and a port without TLS."""

from __future__ import annotations

import os
import socket
from dataclasses import dataclass
from typing import TYPE_CHECKING
from urllib.parse import unquote, urlsplit

from acordcs.runtime.errors import ConfigurationError

if TYPE_CHECKING:
    from acordcs.runtime.context.mqtt import MqttContextProvider

CONTEXT_ENV = "ACORDCS_CONTEXT"
PASSWORD_ENV = "ACORDCS_MQTT_PASSWORD"
CA_ENV = "ACORDCS_MQTT_CA"
EMBEDDED = "embedded"
MQTT_PORT = 1883
MQTTS_PORT = 8883
DEFAULT_PREFIX = "acordcs/ctx"
MIN_KEY_BYTES = 16  # what MqttContextProvider accepts as a payload key


@dataclass(frozen=True)
class BrokerSetting:
    """An MQTT broker's address and the user to log in as (None: anonymous); ``tls``: over TLS."""

    host: str
    port: int = MQTT_PORT
    username: str | None = None
    prefix: str = DEFAULT_PREFIX  # the topics' prefix: <prefix>/<publisher>
    tls: bool = False

    def __str__(self) -> str:
        user = f"{self.username}@" if self.username else ""
        host = f"[{self.host}]" if ":" in self.host else self.host
        prefix = "" if self.prefix == DEFAULT_PREFIX else f"/{self.prefix}"
        return f"{'mqtts' if self.tls else 'mqtt'}://{user}{host}:{self.port}{prefix}"


def parse_context(text: str) -> BrokerSetting | None:
    """``embedded`` (or empty): None; ``mqtt://[USER@]HOST[:PORT][/PREFIX]`` (``mqtts://`` over
    TLS): the broker. ValueError says what is wrong and what to write."""
    text = text.strip()
    if text in ("", EMBEDDED):
        return None
    shape = f"{EMBEDDED!r} or mqtt://[USER@]HOST[:PORT][/PREFIX] (mqtts:// over TLS)"
    parts = urlsplit(text)
    if parts.scheme not in ("mqtt", "mqtts") or not parts.netloc:
        raise ValueError(f"{text!r} is not {shape}")
    if "?" in text or "#" in text:
        raise ValueError(f"{text!r}: no '?' or '#' in a broker's address ({shape})")
    prefix = unquote(parts.path).strip("/") or DEFAULT_PREFIX
    if any(c in prefix for c in "+#\x00") or "//" in prefix:
        raise ValueError(f"{text!r}: the topic prefix {prefix!r} has a wildcard or an empty level")
    if parts.password is not None:
        raise ValueError(
            f"{text!r}: give the broker's password in ${PASSWORD_ENV}, not in the address "
            "(a command line is visible to every user of the machine)"
        )
    try:
        port = parts.port
    except ValueError:
        raise ValueError(f"{text!r}: the port is a whole number 1 to 65535 ({shape})") from None
    if not parts.hostname:
        raise ValueError(f"{text!r} names no host ({shape})")
    if port == 0:
        raise ValueError(f"{text!r}: the port is a whole number 1 to 65535 ({shape})")
    user = unquote(parts.username) if parts.username else None
    tls = parts.scheme == "mqtts"
    return BrokerSetting(
        parts.hostname, port or (MQTTS_PORT if tls else MQTT_PORT), user, prefix, tls
    )


def open_broker(
    setting: BrokerSetting, container: str, *, token: str | None, timeout: float
) -> MqttContextProvider:
    """A client of the broker for ``container``'s process, connected within ``timeout`` seconds
    (a name that does not resolve, a broker that refuses the connection or the login, a peer that
    does not answer as MQTT: ConfigurationError naming the container, host and port)."""
    from acordcs.runtime.context.errors import ContextError
    from acordcs.runtime.context.mqtt import MqttContextProvider

    where = f"container {container!r}"
    what = f"its context broker {setting}"
    try:  # first, so that a name that does not resolve is said as such
        socket.getaddrinfo(setting.host, setting.port, type=socket.SOCK_STREAM)
    except (socket.gaierror, UnicodeError) as err:
        raise ConfigurationError(
            f"{what}: the host name {setting.host!r} does not resolve ({err})",
            where=where,
            hint="give the broker's address in --context mqtt://HOST:PORT (or $ACORDCS_CONTEXT)",
        ) from None
    password = os.environ.get(PASSWORD_ENV) if setting.username else None
    key = token if token and len(token.encode()) >= MIN_KEY_BYTES else None
    ca = (os.environ.get(CA_ENV) or None) if setting.tls else None
    try:
        provider = MqttContextProvider(setting.host, setting.port, qos=1, prefix=setting.prefix,
                                       username=setting.username, password=password,
                                       payload_key=key, connect_timeout=timeout,
                                       tls=setting.tls, tls_ca_certs=ca)  # fmt: skip
    except ContextError as err:
        said = err.message.lower()
        if "ca certificates" in said:
            hint = f"give in ${CA_ENV} the path of a readable PEM file of the broker's CA"
        elif "certificate" in said or "hostname" in said:
            hint = (
                "the broker's certificate must be signed by a CA in "
                f"${CA_ENV} (else the system's) and name the host as the address does"
            )
        elif setting.tls and ("ssl" in said or "eof" in said or "reset" in said):
            hint = (
                "is that port the broker's TLS listener? give that listener's port, or mqtt:// "
                "for a listener without TLS"
            )
        elif "authori" in said or "password" in said:
            hint = (
                "give the broker's user in --context mqtt://USER@HOST:PORT and its password in "
                f"${PASSWORD_ENV}, as the broker's password file has them"
            )
        elif "no connack" in said:
            hint = (
                "what answers there is not an MQTT broker, or not one that answers in time (a "
                "TLS listener needs mqtts://): check the host and port (--context, "
                "$ACORDCS_CONTEXT) and the broker's log"
            )
        else:
            hint = (
                "start the broker there (an MQTT broker such as mosquitto), or give its address "
                "in --context mqtt://HOST:PORT (or $ACORDCS_CONTEXT)"
            )
        raise ConfigurationError(f"{what}: {err.message}", where=where, hint=hint) from None
    return provider


__all__ = ["CA_ENV", "CONTEXT_ENV", "PASSWORD_ENV", "BrokerSetting", "open_broker", "parse_context"]
