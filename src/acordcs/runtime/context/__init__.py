"""Context providers (paper, section 3): publish/subscribe of XML context documents with XPath.

:class:`ContextProvider` runs in-process; :class:`MqttContextProvider` offers the same API across
machines through an MQTT broker (mosquitto), matching in each subscribing client.
"""

from acordcs.runtime.context.delivery import Notification, Subscription, SubscriptionStats
from acordcs.runtime.context.embedded import ContextProvider
from acordcs.runtime.context.errors import ContextError, PublishError, SubscriptionError
from acordcs.runtime.context.index import SubscriptionIndex
from acordcs.runtime.context.mqtt import MqttContextProvider, publisher_topic
from acordcs.runtime.context.xmlparse import Limits

__all__ = [
    "ContextError",
    "ContextProvider",
    "Limits",
    "MqttContextProvider",
    "Notification",
    "PublishError",
    "Subscription",
    "SubscriptionError",
    "SubscriptionIndex",
    "SubscriptionStats",
    "publisher_topic",
]
