"""The distributed context provider: the same API over an MQTT broker (mosquitto) with paho-mqtt 2.x.

Each publisher has a topic (``<prefix>/<publisher percent-escaped>``) carrying its documents, retained
so that late subscribers get the latest one. A broker cannot filter on XML content, so every client
subscribes to the topics it needs and matches locally with the embedded index. Payloads (their
format: :mod:`.mqtt_wire`) carry the publishing process's epoch and a per-publisher sequence
number: gaps are counted as losses (mosquitto drops messages for slow clients beyond
``max_queued_messages``, silently, even at QoS 1).

Against hostile clients of the broker (docs/providers.md, "Security model: MQTT"): with a
``payload_key`` (one per application) payloads carry an HMAC-SHA256 over topic, epoch, sequence
number and document, and clients with the key drop any payload without a valid one; without it, a
sequence jump larger than ``max_seq_jump`` is logged and ignored, and a publisher whose numbers go
back for several documents in a row is resynchronised, so one forged number cannot silence it. A
client keeps the documents of at most ``max_publishers`` publishers (one retained document each).
"""

from __future__ import annotations

import logging
import os
import socket
import threading
import time
from urllib.parse import quote, unquote

import paho.mqtt.client as mqtt
from paho.mqtt.enums import CallbackAPIVersion, MQTTErrorCode

from acordcs.runtime.context.core import ProviderCore, check_publisher
from acordcs.runtime.context.delivery import Subscription
from acordcs.runtime.context.errors import ContextError, PublishError
from acordcs.runtime.context.mqtt_wire import document_payload, end_payload, read_payload
from acordcs.runtime.context.sequences import NEW, REFUSED, SequenceBook, every_power_of_two
from acordcs.runtime.context.xmlparse import Limits, parse_document

log = logging.getLogger("acordcs.runtime.context.mqtt")


def publisher_topic(publisher: str, prefix: str = "acordcs/ctx") -> str:
    """The topic of ``publisher``: every character that MQTT gives a meaning (``/ + # $``) is escaped."""
    return f"{prefix}/{quote(publisher, safe='')}"


class MqttContextProvider(ProviderCore):
    """Context provider whose documents travel through an MQTT broker.

    ``mirror=True`` (default) receives every publisher's documents so that :meth:`query` sees them
    all; with ``mirror=False`` only the topics that local subscriptions need are subscribed.

    ``payload_key`` (bytes or str, the same in every process of the application): sign the
    documents sent and accept only documents signed with it. ``max_publishers``: the publishers
    whose documents this client keeps (others are ignored, counted in ``stats()["refused_publishers"]``).
    ``max_seq_jump``: a larger jump in a publisher's sequence numbers is taken for a forgery.
    Delivery (``inline``): by default (``None``) a subscription starts on the delivery threads,
    and once its callbacks have returned within ``quick_seconds`` 16 times in a row they run in
    paho's network thread, without the hand-over to a delivery thread (which costs a thread
    wake-up per document and, on a busy host, most of the latency: see ``docs/benchmarks.md``).
    A slow subscriber does not stall the network thread: a callback there that takes longer than
    ``quick_seconds`` sends its subscription back to the delivery threads at once (so it held the
    thread for that one callback), and each time it needs twice as many quick callbacks in a row
    to come back (at most 4,096, as long as it overruns again within 4,096 callbacks inline);
    ``Subscription.stats`` count ``inline`` and ``demoted``. The default, 10 ms, is twice the
    interpreter's switch interval: a quick callback kept waiting for the GIL by another thread is
    not taken for slow; nor, on Linux, one the host only preempted (the callback must have waited
    or computed that long, by its thread's ``getrusage``).
    ``inline=False``: always the delivery threads (callbacks that may block without warning, e.g.
    on a remote call, never hold the network thread); ``inline=True``: always the network thread,
    no threads at all (a slow callback holds up every subscription of this client and its
    acknowledgements to the broker).

    ``flush_timeout``: how long :meth:`close` waits for the broker to acknowledge the QoS 1/2
    documents already accepted by :meth:`publish` (queued in the client or in flight); what is
    still unacknowledged then is counted, logged and returned by :meth:`close`, never dropped
    silently. ``clean_session=False`` (with a ``client_id`` of its own, the same at each start):
    the broker keeps this client's subscriptions and queues its QoS 1/2 documents while it is
    away (across the broker's restarts too when the broker persists, ``persistence true``).

    ``tls=True``: TLS to the broker, its certificate verified against the system's CAs, or
    against ``tls_ca_certs`` (a PEM file; giving it implies ``tls``), and its name against ``host``.
    """

    def __init__(
        self,
        host: str = "127.0.0.1",
        port: int = 1883,
        *,
        qos: int = 1,
        prefix: str = "acordcs/ctx",
        client_id: str | None = None,
        mirror: bool = True,
        keepalive: int = 30,
        connect_timeout: float = 5.0,
        max_queued_messages: int = 10_000,
        max_inflight_messages: int = 1000,
        username: str | None = None,
        password: str | None = None,
        tls: bool = False,
        tls_ca_certs: str | None = None,
        limits: Limits | None = None,
        delivery_threads: int = 64,
        payload_key: bytes | str | None = None,
        max_publishers: int = 1000,
        max_seq_jump: int = 1_000_000,
        inline: bool | None = None,
        threads_per_subscriber: int = 2,
        flush_timeout: float = 10.0,
        clean_session: bool = True,
        quick_seconds: float = 0.01,
    ) -> None:
        if not (isinstance(quick_seconds, int | float) and 0 < quick_seconds <= 10):
            raise ContextError(
                f"quick_seconds must be a number of seconds in (0, 10], got {quick_seconds!r}",
                element="MqttContextProvider",
                hint="e.g. 0.01; inline=False to deliver on the delivery threads only",
            )
        super().__init__(
            limits,
            delivery_threads,
            inline=inline is True,
            threads_per_subscriber=threads_per_subscriber,
            quick_seconds=quick_seconds if inline is None else None,
        )
        if max_publishers < 1 or max_seq_jump < 1:
            raise ContextError(
                f"max_publishers and max_seq_jump must be >= 1, got {max_publishers}, {max_seq_jump}",
                element="MqttContextProvider",
            )
        if isinstance(payload_key, str):
            payload_key = payload_key.encode()
        if payload_key is not None and len(payload_key) < 16:
            raise ContextError(
                "payload_key must have at least 16 bytes",
                element="MqttContextProvider",
                hint="use e.g. secrets.token_hex(32), the same in every process of the application",
            )
        self._key = payload_key
        if not clean_session and not client_id:
            raise ContextError(
                "clean_session=False needs a client_id: the broker keeps the session by it",
                element="MqttContextProvider",
                hint="give client_id, the same each time this client starts, unique per client",
            )
        if qos not in (0, 1, 2):
            raise ContextError(f"qos must be 0, 1 or 2, got {qos!r}", element="MqttContextProvider")
        if not prefix or any(c in prefix for c in "+#\x00") or prefix.endswith("/"):
            raise ContextError(
                f"invalid topic prefix {prefix!r}",
                element="MqttContextProvider",
                hint="a topic without wildcards and without a trailing '/', e.g. 'acordcs/ctx'",
            )
        self.host, self.port, self.qos, self.prefix, self.mirror = host, port, qos, prefix, mirror
        tls = tls or tls_ca_certs is not None
        self._where = f"{'mqtts' if tls else 'mqtt'}://{host}:{port}"
        self.malformed = 0  # payloads from the broker that were not ours or not acceptable XML
        self.reconnects = 0
        self.forged = 0  # payloads without a valid signature (with a payload_key)
        self.sequences = SequenceBook(max_publishers, max_seq_jump, self._where)
        # paho's network thread is the only one receiving; the lock keeps documents in order
        # should another ever call _receive (one lock for all: no lock made per document)
        self._receiving = threading.Lock()
        self._publisher_of: dict[str, str] = {}  # topic -> publisher (unquoted once per topic)
        self._epoch = os.urandom(8).hex().encode()
        self._seq: dict[str, int] = {}
        self._topics: set[str] = set()  # what the broker should send us
        # SUBACK may be handled before subscribe() has returned its mid: remember early ones
        self._acks: dict[int, threading.Event] = {}
        self._early_acks: set[int] = set()
        self._ack_lock = threading.Lock()
        self._connected = threading.Event()
        self._connect_error: str | None = None
        self._mqtt_lock = threading.Lock()
        # publishes the broker has not acknowledged yet: mid -> True for a document, False for an
        # end marker; a PUBACK handled before publish() has registered its mid is remembered
        self.flush_timeout = flush_timeout
        self._pending: dict[int, bool] = {}
        self._early_publish_acks: set[int] = set()
        self._flushed = threading.Condition(threading.Lock())
        self.unacknowledged = 0  # documents close() could not get acknowledged (see close)

        client = mqtt.Client(
            CallbackAPIVersion.VERSION2,
            client_id=client_id or f"acordcs-{os.getpid()}-{self._epoch.decode()}",
            protocol=mqtt.MQTTv311,
            clean_session=clean_session,
        )
        client.on_socket_open = self._on_socket_open
        client.on_connect = self._on_connect
        client.on_disconnect = self._on_disconnect
        client.on_subscribe = self._on_subscribe
        client.on_message = self._on_message
        client.on_publish = self._on_publish
        client.reconnect_delay_set(min_delay=1, max_delay=2)
        client.max_queued_messages_set(max_queued_messages)
        # paho's default of 20 unacknowledged QoS 1/2 messages caps a publisher at 20 per round trip
        client.max_inflight_messages_set(max_inflight_messages)
        if username is not None:
            client.username_pw_set(username, password)
        if tls:
            try:  # the CA file read now: a missing or unreadable one is said before connecting
                client.tls_set(ca_certs=tls_ca_certs)  # None: the system's CAs
            except (OSError, ValueError) as err:  # ssl.SSLError is an OSError
                self._closed = True
                raise ContextError(
                    f"cannot use the CA certificates {tls_ca_certs!r} for TLS to the broker: {err}",
                    file=self._where,
                    element="MqttContextProvider",
                    hint="give a readable PEM file of the CA that signed the broker's certificate",
                ) from None
        self._client = client
        try:
            client.connect(host, port, keepalive=keepalive)
        except (OSError, ValueError) as err:
            self._closed = True
            raise ContextError(
                f"cannot reach the MQTT broker at {host}:{port}: {err}",
                file=self._where,
                element="MqttContextProvider",
                hint="start mosquitto there or fix host/port",
            ) from None
        client.loop_start()
        if not self._connected.wait(connect_timeout) or self._connect_error:
            client.loop_stop()
            client.disconnect()
            self._closed = True
            raise ContextError(
                f"the MQTT broker at {host}:{port} did not accept the connection: "
                f"{self._connect_error or f'no CONNACK within {connect_timeout} s'}",
                file=self._where,
                element="MqttContextProvider",
                hint="check the broker's log and its listener/authentication settings",
            )
        self._update_topics()

    # -- paho callbacks (network thread) ------------------------------------------------------------
    def _on_socket_open(self, client: mqtt.Client, _userdata: object, sock: object) -> None:
        # paho never sets TCP_NODELAY: with delayed ACKs small messages wait ~20-40 ms
        if isinstance(sock, socket.socket):
            sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)

    def _on_connect(self, client, _userdata, flags, reason_code, properties) -> None:
        if reason_code.is_failure:
            self._connect_error = str(reason_code)
            self._connected.set()
            return
        kept = flags.session_present  # a persistent session the broker kept (clean_session=False)
        if self._connected.is_set():
            self.reconnects += 1
            log.info(
                "reconnected to %s:%d, %s %d topic(s)",
                self.host,
                self.port,
                "the broker kept the session and its" if kept else "re-subscribing",
                len(self._topics),
            )
        # a clean session (and a restarted broker without persistence) has forgotten our
        # subscriptions: renew them. A kept session has them, and the documents queued for us
        # meanwhile: subscribing again would send the retained latest document before them.
        if not kept:
            with self._mqtt_lock:
                topics = sorted(self._topics)
            for topic in topics:
                client.subscribe(topic, qos=self.qos)
        self._connected.set()

    def _on_disconnect(self, client, _userdata, _flags, reason_code, properties) -> None:
        # a connection the broker refused (_on_connect's error) closes too: the start reports it,
        # and nothing reconnects
        if not self._closed and self._connect_error is None:
            log.warning(
                "lost the MQTT broker at %s:%d (%s); reconnecting",
                self.host,
                self.port,
                reason_code,
            )

    def _on_subscribe(self, client, _userdata, mid, _reason_codes, properties) -> None:
        with self._ack_lock:
            event = self._acks.pop(mid, None)
            if event is None:
                if len(self._early_acks) > 256:  # acks of re-subscriptions nobody waits for
                    self._early_acks.clear()
                self._early_acks.add(mid)
        if event is not None:
            event.set()

    def _on_publish(self, client, _userdata, mid, _reason_code, properties) -> None:
        with self._flushed:
            if self._pending.pop(mid, None) is None:
                if len(self._early_publish_acks) > 65536:  # mids are 16 bits: never ours now
                    self._early_publish_acks.clear()
                self._early_publish_acks.add(mid)
            elif not self._pending:
                self._flushed.notify_all()

    def _sent(self, mid: int, document: bool) -> None:
        """Track the publish ``mid`` until the broker acknowledges it (QoS 0: until written)."""
        with self._flushed:
            if mid in self._early_publish_acks:
                self._early_publish_acks.discard(mid)
            else:
                self._pending[mid] = document

    def _on_message(self, client, _userdata, message: mqtt.MQTTMessage) -> None:
        # an exception escaping a paho callback would end the network thread, silently
        try:
            self._receive(message)
        except Exception as err:
            self.malformed += 1
            # what, where; the traceback only for debugging: a message from the network must not
            # fill the log with one
            log.warning(
                "failed to process a message on %.200r (%s: %.200s); going on",
                message.topic,
                type(err).__name__,
                err,
            )
            log.debug("the failure above", exc_info=True)

    def _receive(self, message: mqtt.MQTTMessage) -> None:
        topic = message.topic
        publisher = self._publisher_of.get(topic)
        if publisher is None:
            if not topic.startswith(self.prefix + "/"):
                return
            publisher = unquote(topic[len(self.prefix) + 1 :])
            if len(self._publisher_of) >= 2 * self.sequences.max_publishers:
                self._publisher_of.clear()  # hostile topics cannot grow it without bound
            self._publisher_of[topic] = publisher
        payload = message.payload
        if not payload:  # an empty retained message: the publisher was retired (see ``retire``)
            with self._lock:
                self._latest.pop(publisher, None)
            self.sequences.forget(publisher)
            return
        read = read_payload(payload)
        if read is None:
            self.malformed += 1
            if every_power_of_two(self.malformed):
                log.warning(
                    "ignoring a message on %s that is not an acordcs context document (%d so far)",
                    topic,
                    self.malformed,
                )
            return
        if self._key is not None and not read.signed_by(self._key, topic):
            self.forged += 1
            if every_power_of_two(self.forged):
                log.warning(
                    "ignoring a document on %s without a valid signature (%d so far): another "
                    "client of the broker wrote it, or its sender has another payload_key",
                    topic,
                    self.forged,
                )
            return
        epoch, seq, body = read.epoch, read.seq, read.body
        if read.end:
            self.sequences.ended_at(publisher, epoch, seq)
            return
        admitted = self.sequences.admit(publisher, epoch, seq)
        if admitted == REFUSED:
            return
        try:
            tree = parse_document(publisher, body, self.limits)
        except PublishError as err:
            self.malformed += 1
            self._count_rejected(publisher)
            log.warning("ignoring a refused document from the broker: %s", err)
            return
        try:
            with self._receiving:
                self._dispatch(publisher, seq, tree, latest=admitted == NEW, may_inline=True)
        finally:  # what was matched before a failure is delivered all the same
            self._dispatcher.flush()  # quick subscriptions' callbacks run now, outside the locks

    # -- topics ---------------------------------------------------------------------------------------
    def _wanted(self) -> set[str]:
        subs = self.subscriptions()
        if self.mirror or any(s.publisher is None for s in subs):
            return {f"{self.prefix}/+"}
        return {publisher_topic(s.publisher, self.prefix) for s in subs if s.publisher is not None}

    def _update_topics(self, timeout: float = 5.0) -> None:
        if self._closed:
            return
        with self._mqtt_lock:
            wanted = self._wanted()
            added, removed = wanted - self._topics, self._topics - wanted
            self._topics = wanted
            events = []
            for topic in sorted(added):
                rc, mid = self._client.subscribe(topic, qos=self.qos)
                if rc == MQTTErrorCode.MQTT_ERR_SUCCESS and mid is not None:
                    with self._ack_lock:
                        if mid in self._early_acks:
                            self._early_acks.discard(mid)
                            continue
                        event = self._acks[mid] = threading.Event()
                    events.append(event)
            for topic in sorted(removed):
                self._client.unsubscribe(topic)
        # wait for SUBACK so that a publish right after subscribe() reaches the new subscriber;
        # while disconnected there is nothing to wait for (on_connect subscribes)
        for event in events:
            event.wait(timeout)

    def _subscribed(self, sub: Subscription) -> None:
        self._update_topics()

    def _unsubscribed(self, sub: Subscription) -> None:
        self._update_topics()

    # -- publishing -----------------------------------------------------------------------------------
    def publish(self, publisher: str, document: object) -> int:
        """Send ``document`` to the broker as ``publisher``'s latest (retained) context.

        The document is checked here with the same limits subscribers apply, so a refused document
        raises :class:`PublishError` and is not sent. Returns its sequence number. While the broker
        is unreachable, QoS 0 raises :class:`ContextError`; QoS 1 and 2 queue up to
        ``max_queued_messages`` documents in the client for when it reconnects.
        """
        self._check_open()
        topic = publisher_topic(check_publisher(publisher), self.prefix)
        data, _ = self._parse(publisher, document)
        with self._mqtt_lock:
            seq = self._seq.get(publisher, 0) + 1
            payload = document_payload(self._key, topic, self._epoch, seq, data)
            info = self._client.publish(topic, payload, qos=self.qos, retain=True)
            if info.rc == MQTTErrorCode.MQTT_ERR_SUCCESS or (
                info.rc == MQTTErrorCode.MQTT_ERR_NO_CONN and self.qos > 0
            ):
                self._seq[publisher] = seq
                self._sent(info.mid, True)
                return seq
        reason = mqtt.error_string(info.rc)
        raise ContextError(
            f"document from {publisher!r} not sent to {self.host}:{self.port}: {reason}",
            file=self._where,
            element="publish",
            hint=(
                "the broker is unreachable: retry later, or use qos=1 to queue while disconnected"
                if self.qos == 0
                else "the client's queue (max_queued_messages) is full: the broker is unreachable or "
                "slower than the publisher; retry later"
            ),
        )

    def retire(self, publisher: str) -> None:
        """Clear ``publisher``'s retained document at the broker (retained documents otherwise outlive
        their publisher forever); clients drop it from ``latest``/``query``, nobody is notified."""
        self._check_open()
        topic = publisher_topic(check_publisher(publisher), self.prefix)
        with self._mqtt_lock:
            # the sequence goes on: a client that missed this must not take later documents for repeats
            info = self._client.publish(topic, b"", qos=self.qos, retain=True)
            if info.rc in (MQTTErrorCode.MQTT_ERR_SUCCESS, MQTTErrorCode.MQTT_ERR_NO_CONN):
                self._sent(info.mid, False)
        if info.rc not in (MQTTErrorCode.MQTT_ERR_SUCCESS, MQTTErrorCode.MQTT_ERR_NO_CONN):
            raise ContextError(
                f"could not retire {publisher!r}: {mqtt.error_string(info.rc)}",
                file=self._where,
                element="retire",
                hint="retry once the broker is reachable",
            )

    @property
    def connected(self) -> bool:
        return self._client.is_connected()

    def stats(self) -> dict[str, object]:
        figures = super().stats()
        figures.update(
            **self.sequences.figures(),
            malformed=self.malformed,
            reconnects=self.reconnects,
            forged=self.forged,
            unacknowledged=self.unacknowledged if self._closed else self.pending(),
        )
        return figures

    def pending(self) -> int:
        """Documents accepted by :meth:`publish` that the broker has not acknowledged yet."""
        with self._flushed:
            return sum(self._pending.values())

    def flush(self, timeout: float | None = None) -> int:
        """Wait up to ``timeout`` s (default ``flush_timeout``) until the broker has acknowledged
        every document published so far; returns how many it has not."""
        deadline = time.monotonic() + (self.flush_timeout if timeout is None else timeout)
        with self._flushed:
            while self._pending and (left := deadline - time.monotonic()) > 0:
                self._flushed.wait(left)
            return sum(self._pending.values())

    def _send_end_markers(self) -> None:
        with self._mqtt_lock:
            for publisher, seq in self._seq.items():
                topic = publisher_topic(publisher, self.prefix)
                payload = end_payload(self._key, topic, self._epoch, seq)
                info = self._client.publish(topic, payload, qos=self.qos, retain=False)
                if info.rc in (MQTTErrorCode.MQTT_ERR_SUCCESS, MQTTErrorCode.MQTT_ERR_NO_CONN):
                    self._sent(info.mid, False)

    def close(self, timeout: float | None = None) -> int:
        """Flush, unsubscribe everything, disconnect and stop the network thread. Idempotent.

        Before disconnecting, tells the subscribers each publisher's last sequence number (so a
        lost tail is counted as lost there) and waits up to ``timeout`` s (default
        ``flush_timeout``) for the broker's acknowledgements of every document published here.
        Returns the number of documents still unacknowledged then (0: the broker has them all),
        also logged as a warning and kept in ``stats()["unacknowledged"]``."""
        if self._closed:
            return self.unacknowledged
        if self._seq:
            self._send_end_markers()
        wait = self.flush_timeout if timeout is None else timeout
        started = time.monotonic()
        self.unacknowledged = self.flush(wait)
        reachable = self._client.is_connected()
        super().close()
        self._client.disconnect()
        self._client.loop_stop()
        if self.unacknowledged:
            log.warning(
                "%s: closed with %d document(s) not acknowledged by the broker within %g s "
                "(%s): they may never reach the subscribers, who count them as lost only if "
                "later documents or this publisher's end marker reach them",
                self._where,
                self.unacknowledged,
                time.monotonic() - started,
                "connected" if reachable else "the broker is unreachable",
            )
        return self.unacknowledged
