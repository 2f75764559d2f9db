package org.acordcs.runtime;

import java.util.ArrayList;
import java.util.Collections;
import java.util.LinkedHashMap;
import java.util.List;
import java.util.Map;
import java.util.Objects;

/**
 * The base class of every component (paper, section 3: components inherit from
 * {@code CtxComponent}): its name, its ports by name, and its typed properties read and written
 * by name (what a policy's rules adapt). A generated {@code <Component>Base} class implements the
 * property methods over its typed fields; the user's {@code <Component>} subclass implements the
 * operations.
 *
 * <p>A component tagged {@code language=java} is hosted by its container (acordcs.runtime.jvm):
 * the container gives it a {@link Host}, through which its ports call, notify and push (each port
 * through its own {@link Port.Link}), its
 * setters change its properties (so that policies and monitors see the change), and
 * {@link #ruleEngine} reaches a policy set's engine. The container keeps the property fields
 * current: a policy's write lands in the field, then {@link #onPropertyChanged} runs.
 */
public abstract class CtxComponent {
    /** What the container hosting a component gives it (implemented by the container). */
    public interface Host {
        /**
         * The container's end of port {@code port}: asked once for each port when the component
         * is hosted, so that each call, notification or item goes straight to that port.
         */
        Port.Link link(String port);

        /** Sets property {@code property} through the container (policies and monitors see it). */
        void set(String property, Object value);

        /** The rule engine of policy set {@code policySet} of the container. */
        RuleEngine ruleEngine(String policySet);
    }

    private final String name;
    private final Map<String, Port> ports = new LinkedHashMap<>();
    private Host host;

    protected CtxComponent(String name) {
        this.name = Objects.requireNonNull(name, "name");
    }

    /** The component's name, as the model names it. */
    public final String componentName() {
        return name;
    }

    /** Adds {@code port}; a second port of the same name is an IllegalArgumentException. */
    protected final Port addPort(Port port) {
        Objects.requireNonNull(port, "port");
        if (ports.putIfAbsent(port.name(), port) != null) {
            throw new IllegalArgumentException(name + " already has a port " + port.name());
        }
        return port;
    }

    /** Called once by the container hosting the component; a second call is an IllegalStateException. */
    public final void attachHost(Host host) {
        Objects.requireNonNull(host, "host");
        if (this.host != null) {
            throw new IllegalStateException(name + " is already hosted");
        }
        this.host = host;
        for (Port port : ports.values()) {
            port.link = host.link(port.name());
        }
    }

    /** The container's host, or null when the component is not hosted (constructed by hand). */
    public final Host host() {
        return host;
    }

    /**
     * Sets property {@code property} through the container when hosted (it then writes the field
     * back, and policies and monitors see the change): true; false when not hosted (the caller
     * sets its field itself). The generated setters call it.
     */
    protected final boolean hostSet(String property, Object value) {
        if (host == null) {
            return false;
        }
        host.set(property, value);
        return true;
    }

    /**
     * The paper's rule-engine interface over policy set {@code policySet} of the container: the
     * component's own rules ({@code defrule}) in a rule set named after it, over the variables
     * of that policy set.
     *
     * @throws IllegalStateException when the component is not hosted
     */
    public final RuleEngine ruleEngine(String policySet) {
        if (host == null) {
            throw new IllegalStateException(name + " is not hosted: no rule engine");
        }
        return host.ruleEngine(policySet);
    }

    /** Called once hosted (ports and properties ready), and after a replacement. */
    public void onStart() {
    }

    /** Called before the component is destroyed or replaced. */
    public void onStop() {
    }

    /** Called after property {@code property} changed (its field already holds {@code value}). */
    public void onPropertyChanged(String property, Object old, Object value) {
    }

    /** Called with each message (asynchronous port) or item (stream port) arriving at {@code port}. */
    public void onMessage(String port, Object message) {
    }

    /**
     * The port named {@code portName}.
     *
     * @throws IllegalArgumentException when the component has no such port
     */
    public final Port port(String portName) {
        Port port = ports.get(portName);
        if (port == null) {
            throw new IllegalArgumentException(name + " has no port " + portName);
        }
        return port;
    }

    /** The ports, in the model's order. */
    public final List<Port> ports() {
        return Collections.unmodifiableList(new ArrayList<>(ports.values()));
    }

    /** The names of the properties, in the model's order. */
    public abstract List<String> propertyNames();

    /** The Java type of property {@code property} (Integer.class for an int, and so on). */
    public abstract Class<?> propertyType(String property);

    /** The value of property {@code property}, boxed. */
    public abstract Object getProperty(String property);

    /**
     * Sets property {@code property} to {@code value}, converted to its type: a number to an int,
     * long or double property (an int or long is truncated toward zero), a Boolean to a boolean
     * property, anything to a String property (its toString).
     *
     * @throws IllegalArgumentException for an unknown property or a value that does not fit
     */
    public abstract void setProperty(String property, Object value);

    protected static int asInt(String property, Object value) {
        return (int) asLong(property, value);
    }

    protected static long asLong(String property, Object value) {
        if (value instanceof Number) {
            return ((Number) value).longValue();
        }
        throw new IllegalArgumentException(property + " takes a number, not " + value);
    }

    protected static double asDouble(String property, Object value) {
        if (value instanceof Number) {
            return ((Number) value).doubleValue();
        }
        throw new IllegalArgumentException(property + " takes a number, not " + value);
    }

    protected static boolean asBoolean(String property, Object value) {
        if (value instanceof Boolean) {
            return (Boolean) value;
        }
        throw new IllegalArgumentException(property + " takes a Boolean, not " + value);
    }

    protected static String asString(String property, Object value) {
        if (value == null) {
            throw new IllegalArgumentException(property + " takes a String, not null");
        }
        return value.toString();
    }

    protected static IllegalArgumentException unknownProperty(String component, String property) {
        return new IllegalArgumentException(component + " has no property " + property);
    }

    @Override
    public String toString() {
        return getClass().getSimpleName() + "(" + name + ")";
    }
}
