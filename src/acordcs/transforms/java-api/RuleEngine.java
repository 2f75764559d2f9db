package org.acordcs.runtime;

/**
 * The ACORD-CS interface to a rule engine (paper, section 3): four calls. A policy set holds one
 * engine; its monitor sets the context variables, fires, and the adaptation reads the results.
 *
 * <p>Variables are named as the model names them, {@code Element.attribute} (for example
 * {@code Locomotion.maxSpeed}); the engine checks that a rule names only known variables.
 */
public interface RuleEngine {
    /** Adds a rule, or replaces the rule with the same label, written in the engine's syntax. */
    void defrule(String rule);

    /** Asserts {@code value} for {@code variable}, an attribute of a model element. */
    void set(String variable, Object value);

    /** Fires the rules: every variable a rule concludes on gets its new value. */
    void fire();

    /** The current value of {@code variable}. */
    Object get(String variable);
}
