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

    /**
     * The container's end of a port of a hosted component (implemented by the container, one per
     * port): what {@link #call}, {@link #notify} and {@link #push} go through. A call without
     * arguments or with one has a method of its own, so that no array crosses to the container.
     */
    public interface Link {
        /** Calls {@code operation} without arguments through the port; its result, boxed. */
        Object call0(String operation);

        /** Calls {@code operation} with one argument through the port; its result, boxed. */
        Object call1(String operation, Object arg);

        /** Calls {@code operation} with {@code args} through the port; its result, boxed. */
        Object call(String operation, Object[] args);

        /** Sends {@code message} through the port. */
        void notify(Object message);

        /** Pushes {@code item} through the port. */
        void push(Object item);
    }

    private final String name;
    private final Kind kind;
    private final Role role;
    private Port peer;
    Link link; // set by CtxComponent.attachHost

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
        Link to = hosted("call");
        switch (args.length) {
            case 0: return to.call0(operation);
            case 1: return to.call1(operation, args[0]);
            default: return to.call(operation, args);
        }
    }

    /** Sends {@code message} to every peer of this asynchronous port, through the container. */
    public void notify(Object message) {
        hosted("notify").notify(message);
    }

    /** Pushes {@code item} to the consumers of this stream port, through the container. */
    public void push(Object item) {
        hosted("push").push(item);
    }

    private Link hosted(String what) {
        if (link == null) {
            throw new IllegalStateException(
                    "port " + name + ": cannot " + what + ": its component is not hosted by a container");
        }
        return link;
    }

    @Override
    public String toString() {
        return "Port(" + name + ", " + kind + ", " + role + ")";
    }
}
