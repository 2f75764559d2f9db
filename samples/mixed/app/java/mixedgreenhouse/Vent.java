// Created by acordcs-gen 0.1.0 (target java) from component 'Vent' (Vent, id _Vent)
// in model file greenhouse.uml. Written once: yours to edit, never overwritten by a build.
package mixedgreenhouse;

/**
 * The greenhouse's vent, in Java: the Ventilation policy set sets its {@code opening}; its report
 * asks the sensor (Python) for the temperature through {@code ThermoPort}; {@code advise} uses the
 * paper's four rule-engine calls over the Ventilation policy set's engine; it sends the sensor an
 * alarm on {@code AlarmPort} when it refuses a calibration, and keeps the sensor's last notice.
 */
public class Vent extends VentBase {
    private int changes;
    private java.lang.String notice = "";

    public Vent() {
        super();
    }

    @java.lang.Override
    public java.lang.String report() {
        double temperature = ((Number) ThermoPort.call("readTemperature")).doubleValue();
        return java.lang.String.format(java.util.Locale.ROOT,
                "opening %.1f %% at %.1f C after %d change(s)", opening, temperature, changes);
    }

    /** The opening its own two rules advise at {@code temperature}, in the policy set's engine. */
    @java.lang.Override
    public double advise(double temperature) {
        org.acordcs.runtime.RuleEngine rules = ruleEngine("Ventilation");
        rules.defrule("own_cool: if temperature is cool then Vent.opening is closed");
        rules.defrule("own_hot: if temperature is hot then Vent.opening is wide");
        rules.set("temperature", temperature);
        rules.fire();
        return ((Number) rules.get("Vent.opening")).doubleValue();
    }

    @java.lang.Override
    public double calibrate(double reference) {
        if (reference < 0 || reference > 50) {
            AlarmPort.notify("calibration to " + reference + " C refused");
            throw new java.lang.IllegalArgumentException(
                    "reference " + reference + " C is outside the sensor's range, 0 to 50 C");
        }
        return reference - ((Number) ThermoPort.call("readTemperature")).doubleValue();
    }

    @java.lang.Override
    public java.lang.String lastNotice() {
        return notice;
    }

    /** A notice from the sensor, on {@code NoticeInPort}. */
    @java.lang.Override
    public void onMessage(java.lang.String port, java.lang.Object message) {
        notice = port + ": " + message;
    }

    @java.lang.Override
    public void onPropertyChanged(java.lang.String property, java.lang.Object old, java.lang.Object value) {
        changes++;
    }
}
