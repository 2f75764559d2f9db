package org.acordcs.runtime;

import java.util.Objects;

/**
 * A port of a component (paper, section 3: {@code CtxPort}): its name, its kind (synchronous,
 * asynchronous or stream) and its role (provided or required). A required port is connected to
 * one provided port of the same kind ({@code CtxPortConnection}).
 */
public final class Port {
    /** How calls go through the port. */
    public enum Kind { SYNCHRONOUS, ASYNCHRONOUS, STREAM }

    /** Whether the component offers the port's service or uses another's. */
    public enum Role { PROVIDED, REQUIRED }

    private final String name;
    private final Kind kind;
    private final Role role;
    private Port peer;
    CtxComponent owner; // set by CtxComponent.addPort

    public Port(String name, Kind kind, Role role) {
        this.name = Objects.requireNonNull(name, "name");
        this.kind = Objects.requireNonNull(kind, "kind");
        this.role = Objects.requireNonNull(role, "role");
    }

    public String name() {
        return name;
    }

    public Kind kind() {
        return kind;
    }

    public Role role() {
        return role;
    }

    /** The provided port this required port is connected to, or the required port connected to
     * this provided one; null when unconnected. */
    public Port peer() {
        return peer;
    }

    /**
     * Connects this required port to {@code provided}, a provided port of the same kind.
     *
     * @throws IllegalArgumentException when the roles or kinds do not fit, or either port is
     *     already connected
     */
    public void connect(Port provided) {
        Objects.requireNonNull(provided, "provided");
        if (role != Role.REQUIRED || provided.role != Role.PROVIDED) {
            throw new IllegalArgumentException(
                    "connect a required port to a provided one: " + name + " -> " + provided.name);
        }
        if (kind != provided.kind) {
            throw new IllegalArgumentException(
                    "ports of different kinds: " + name + " (" + kind + ") -> " + provided.name
                            + " (" + provided.kind + ")");
        }
        if (peer != null || provided.peer != null) {
            throw new IllegalArgumentException("already connected: " + name + " or " + provided.name);
        }
        peer = provided;
        provided.peer = this;
    }

    /**
     * Calls {@code operation} of the component this synchronous required port is connected to,
     * through the container (interceptors, connectors, remote containers); its result, boxed.
     *
     * @throws IllegalStateException when the component is not hosted
     */
    public Object call(String operation, Object... args) {
        return hosted("call").call(name, operation, args);
    }

    /** Sends {@code message} to every peer of this asynchronous port, through the container. */
    public void notify(Object message) {
        hosted("notify").notify(name, message);
    }

    /** Pushes {@code item} to the consumers of this stream port, through the container. */
    public void push(Object item) {
        hosted("push").push(name, item);
    }

    private CtxComponent.Host hosted(String what) {
        CtxComponent.Host host = owner == null ? null : owner.host();
        if (host == null) {
            throw new IllegalStateException(
                    "port " + name + ": cannot " + what + ": its component is not hosted by a container");
        }
        return host;
    }

    @Override
    public String toString() {
        return "Port(" + name + ", " + kind + ", " + role + ")";
    }
}
