"""The embedded (in-process) context provider, the default."""

from __future__ import annotations

from acordcs.runtime.context.core import ProviderCore, check_publisher
from acordcs.runtime.context.xmlparse import Limits


class ContextProvider(ProviderCore):
    """Publish/subscribe of XML context documents within one process::

    provider = ContextProvider()
    provider.subscribe(on_low_battery, "/robot/battery[. < 20]")
    provider.publish("robot1", "<robot><battery>15</battery></robot>")  # -> 1, the sequence number

    ``inline=True`` delivers in the publishing thread, for deterministic virtual-time runs.
    """

    def __init__(
        self,
        limits: Limits | None = None,
        *,
        delivery_threads: int = 64,
        inline: bool = False,
        threads_per_subscriber: int = 2,
    ) -> None:
        super().__init__(
            limits, delivery_threads, inline=inline, threads_per_subscriber=threads_per_subscriber
        )
        self._seq: dict[str, int] = {}

    def publish(self, publisher: str, document: object) -> int:
        """Publish ``document`` (bytes, str or lxml element) as ``publisher``'s latest context.

        Returns its sequence number. A refused document raises
        :class:`~acordcs.runtime.context.errors.PublishError` and changes nothing.
        """
        self._check_open()
        check_publisher(publisher)
        _, tree = self._parse(publisher, document)
        with self._publishing(publisher):  # not the provider lock: see _dispatch
            seq = self._seq.get(publisher, 0) + 1
            self._seq[publisher] = seq
            self._dispatch(publisher, seq, tree)
        self._dispatcher.flush()  # inline delivery: the callbacks run now, outside the lock
        return seq
