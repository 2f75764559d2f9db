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
 */
public abstract class CtxComponent {
    private final String name;
    private final Map<String, Port> ports = new LinkedHashMap<>();

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
