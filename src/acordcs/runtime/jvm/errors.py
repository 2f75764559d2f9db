"""What hosting a Java component can fail with: :class:`JavaHostError` (not started: no JPype,
no JDK, sources that do not compile, a class that does not fit its model) and
:class:`JavaFault` (a Java exception thrown by a hosted component's code: a fault)."""

from __future__ import annotations

from acordcs.errors import AcordError


class JavaHostError(AcordError):
    """A component tagged ``language=java`` that its container cannot host; it names the
    component, what is missing or wrong, where (the Java source's ``file:line`` when javac
    gives one) and what to do. The container does not start (exit 2)."""

    exit_code = 2

    def location(self) -> str:
        return super().location() if self.file else "java host"


class JavaFault(Exception):
    """A Java exception thrown by a hosted Java component (an operation, a hook): its class, its
    message and the component's part of its Java stack trace (``java_stack``). Not an
    :class:`~acordcs.errors.AcordError`: like a Python component's exception, the container
    records it as a fault of the component and goes on."""

    def __init__(self, message: str, java_stack: str) -> None:
        super().__init__(f"{message}\n{java_stack}" if java_stack else message)
        self.java_stack = java_stack
