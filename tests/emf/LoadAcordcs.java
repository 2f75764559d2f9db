import java.io.File;
import java.util.Collection;
import java.util.List;
import java.util.Map;
import java.util.TreeMap;

import org.eclipse.emf.common.util.Diagnostic;
import org.eclipse.emf.common.util.TreeIterator;
import org.eclipse.emf.common.util.URI;
import org.eclipse.emf.ecore.EAttribute;
import org.eclipse.emf.ecore.EObject;
import org.eclipse.emf.ecore.EPackage;
import org.eclipse.emf.ecore.EReference;
import org.eclipse.emf.ecore.EStructuralFeature;
import org.eclipse.emf.ecore.resource.Resource;
import org.eclipse.emf.ecore.resource.ResourceSet;
import org.eclipse.emf.ecore.resource.impl.ResourceSetImpl;
import org.eclipse.emf.ecore.util.Diagnostician;
import org.eclipse.emf.ecore.util.EcoreUtil;
import org.eclipse.emf.ecore.xmi.impl.EcoreResourceFactoryImpl;
import org.eclipse.emf.ecore.xmi.impl.XMIResourceFactoryImpl;

/**
 * Loads the ACORD-CS metamodel and model instance files in Eclipse EMF itself (no pyecore), as the
 * proof that what our toolchain writes is real Ecore/XMI.
 *
 * <p>Usage: {@code LoadAcordcs ECORE [MODEL...]}. Validates the EPackage with EMF's Diagnostician,
 * registers it, loads every MODEL, resolves every reference, validates every root and prints, one
 * record per line, fields separated by TAB (tabs, newlines and backslashes in values escaped as
 * {@code \t \n \\}). {@code LoadAcordcs --by-schema-location MODEL...} registers no metamodel:
 * EMF must find it where each MODEL's {@code xsi:schemaLocation} says, as an EMF tool opening the
 * file would.
 * <ul>
 *   <li>{@code metamodel MODEL nsURI location}: where the EPackage of the model's root was loaded
 *       from (its resource's URI);</li>
 *   <li>{@code count MODEL EClass n}: objects per EClass, the root included;</li>
 *   <li>{@code attr MODEL fragment feature set kind value}: every attribute of every object as EMF
 *       sees it ({@code set} is eIsSet; kind {@code null}, {@code one} or {@code many}, many values
 *       separated by U+001F);</li>
 *   <li>{@code ref MODEL fragment feature targets}: every non-containment reference, targets as
 *       URI fragments separated by U+001F;</li>
 *   <li>{@code problem where severity message}: a resource diagnostic or a Diagnostician finding.</li>
 * </ul>
 * Exit 0 when nothing was reported, 1 on any error or warning, 2 when the arguments or files are
 * unusable.
 */
public final class LoadAcordcs {
    private static final char SEP = '\u001f';
    private static int problems = 0;

    private LoadAcordcs() {}

    public static void main(String[] args) {
        if (args.length < 1) {
            System.err.println("usage: LoadAcordcs ECORE [MODEL...] (the metamodel, then model instance files), "
                    + "or LoadAcordcs --by-schema-location MODEL...");
            System.exit(2);
        }
        boolean bySchemaLocation = "--by-schema-location".equals(args[0]);
        for (int i = bySchemaLocation ? 1 : 0; i < args.length; i++) {
            String a = args[i];
            if (!new File(a).isFile()) {
                System.err.println("LoadAcordcs: no such file: " + a + " (pass existing .ecore and .xmi paths)");
                System.exit(2);
            }
        }
        ResourceSet rs = new ResourceSetImpl();
        Map<String, Object> factories = rs.getResourceFactoryRegistry().getExtensionToFactoryMap();
        factories.put("ecore", new EcoreResourceFactoryImpl());
        factories.put(Resource.Factory.Registry.DEFAULT_EXTENSION, new XMIResourceFactoryImpl());

        if (!bySchemaLocation) {
            EPackage pkg = loadMetamodel(rs, args[0]);
            rs.getPackageRegistry().put(pkg.getNsURI(), pkg);
        }
        for (int i = 1; i < args.length; i++) {
            loadModel(rs, args[i]);
        }
        System.out.println("problems\t" + problems);
        System.exit(problems == 0 ? 0 : 1);
    }

    private static Resource load(ResourceSet rs, String path) {
        try {
            return rs.getResource(URI.createFileURI(new File(path).getAbsolutePath()), true);
        } catch (RuntimeException e) {
            // EMF wraps parse and resolution failures; the cause says which line of which file.
            Throwable cause = e.getCause() != null ? e.getCause() : e;
            System.err.println("LoadAcordcs: cannot load " + path + ": " + cause);
            System.exit(1);
            return null;
        }
    }

    private static void reportResource(String where, Resource res) {
        for (Resource.Diagnostic d : res.getErrors()) {
            problem(where + ":" + d.getLine() + ":" + d.getColumn(), "ERROR", d.getMessage());
        }
        for (Resource.Diagnostic d : res.getWarnings()) {
            problem(where + ":" + d.getLine() + ":" + d.getColumn(), "WARNING", d.getMessage());
        }
    }

    private static EPackage loadMetamodel(ResourceSet rs, String path) {
        Resource res = load(rs, path);
        reportResource(path, res);
        if (res.getContents().size() != 1 || !(res.getContents().get(0) instanceof EPackage)) {
            System.err.println("LoadAcordcs: " + path + " does not hold exactly one EPackage");
            System.exit(1);
        }
        EPackage pkg = (EPackage) res.getContents().get(0);
        report(path, Diagnostician.INSTANCE.validate(pkg));
        System.out.println("epackage\t" + pkg.getName() + "\t" + pkg.getNsURI() + "\t"
                + pkg.getEClassifiers().size() + " classifiers");
        return pkg;
    }

    private static void loadModel(ResourceSet rs, String path) {
        Resource res = load(rs, path);
        EcoreUtil.resolveAll(res);
        reportResource(path, res);
        Map<EObject, Collection<EStructuralFeature.Setting>> unresolved =
                EcoreUtil.UnresolvedProxyCrossReferencer.find(res);
        for (Map.Entry<EObject, Collection<EStructuralFeature.Setting>> e : unresolved.entrySet()) {
            problem(path, "ERROR", "unresolved reference " + EcoreUtil.getURI(e.getKey()));
        }
        Map<String, Integer> counts = new TreeMap<>();
        List<EObject> roots = res.getContents();
        if (roots.isEmpty()) {
            problem(path, "ERROR", "the resource is empty");
        }
        for (EObject root : roots) {
            EPackage metamodel = root.eClass().getEPackage();
            Resource from = metamodel.eResource();
            System.out.println("metamodel\t" + path + "\t" + metamodel.getNsURI() + "\t"
                    + (from == null ? "" : from.getURI().toFileString()));
            report(path, Diagnostician.INSTANCE.validate(root));
            counts.merge(root.eClass().getName(), 1, Integer::sum);
            for (TreeIterator<EObject> it = root.eAllContents(); it.hasNext();) {
                counts.merge(it.next().eClass().getName(), 1, Integer::sum);
            }
        }
        for (Map.Entry<String, Integer> e : counts.entrySet()) {
            System.out.println("count\t" + path + "\t" + e.getKey() + "\t" + e.getValue());
        }
        for (EObject root : roots) {
            dump(path, root);
            for (TreeIterator<EObject> it = root.eAllContents(); it.hasNext();) {
                dump(path, it.next());
            }
        }
    }

    private static void dump(String path, EObject obj) {
        String frag = EcoreUtil.getURI(obj).fragment();
        for (EAttribute a : obj.eClass().getEAllAttributes()) {
            Object value = obj.eGet(a);
            String kind;
            String text;
            if (a.isMany()) {
                kind = "many";
                StringBuilder sb = new StringBuilder();
                for (Object v : (List<?>) value) {
                    if (sb.length() > 0) {
                        sb.append(SEP);
                    }
                    sb.append(EcoreUtil.convertToString(a.getEAttributeType(), v));
                }
                text = sb.toString();
            } else if (value == null) {
                kind = "null";
                text = "";
            } else {
                kind = "one";
                text = EcoreUtil.convertToString(a.getEAttributeType(), value);
            }
            System.out.println("attr\t" + path + "\t" + frag + "\t" + a.getName() + "\t" + obj.eIsSet(a)
                    + "\t" + kind + "\t" + escape(text));
        }
        for (EReference r : obj.eClass().getEAllReferences()) {
            if (r.isContainment() || r.isContainer()) {
                continue;
            }
            StringBuilder sb = new StringBuilder();
            Object value = obj.eGet(r);
            List<?> targets = r.isMany() ? (List<?>) value : (value == null ? List.of() : List.of(value));
            for (Object t : targets) {
                if (sb.length() > 0) {
                    sb.append(SEP);
                }
                sb.append(EcoreUtil.getURI((EObject) t).fragment());
            }
            System.out.println("ref\t" + path + "\t" + frag + "\t" + r.getName() + "\t" + escape(sb.toString()));
        }
    }

    private static String escape(String s) {
        return s.replace("\\", "\\\\").replace("\t", "\\t").replace("\n", "\\n");
    }

    private static void report(String where, Diagnostic diagnostic) {
        if (diagnostic.getSeverity() == Diagnostic.OK) {
            return;
        }
        if (diagnostic.getChildren().isEmpty()) {
            problem(where, severity(diagnostic.getSeverity()), diagnostic.getMessage());
        }
        for (Diagnostic child : diagnostic.getChildren()) {
            report(where, child);
        }
    }

    private static String severity(int s) {
        switch (s) {
            case Diagnostic.ERROR: return "ERROR";
            case Diagnostic.WARNING: return "WARNING";
            case Diagnostic.CANCEL: return "CANCEL";
            case Diagnostic.INFO: return "INFO";
            default: return "OK";
        }
    }

    private static void problem(String where, String severity, String message) {
        // INFO is EMF telling, not complaining; everything else fails the run.
        if (!"INFO".equals(severity)) {
            problems++;
        }
        System.out.println("problem\t" + where + "\t" + severity + "\t" + escape(message));
    }
}
