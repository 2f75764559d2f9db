"""What the XMI readers share: primitive type names, known UML metaclasses, id bookkeeping."""

from __future__ import annotations

from collections import defaultdict

from acordcs.diagnostics import diagnostic
from acordcs.xmi.uml import UmlModel

# The fragment of an OMG / Eclipse primitive-type href -> the type name a modeller writes. Never fetched.
PRIMITIVE_TYPES = {
    "string": "string",
    "integer": "int",
    "boolean": "bool",
    "real": "double",
    "unlimitednatural": "long",  # BOUML writes its `long` as UnlimitedNatural
    "estring": "string",
    "eint": "int",
    "eboolean": "bool",
    "edouble": "double",
    "efloat": "float",
    "elong": "long",
    "double": "double",
    "int": "int",
    "float": "float",
    "long": "long",
    "char": "char",
    "byte": "byte",
    "short": "short",
    "boolean_": "bool",
}


def primitive_from_href(href: str) -> str:
    fragment = href.rpartition("#")[2]
    return PRIMITIVE_TYPES.get(fragment.lower(), fragment)


# Concrete UML 2.5 metaclasses: an xmi:type outside this set is reported (R201).
UML_METACLASSES = frozenset(
    [
        "Abstraction",
        "AcceptCallAction",
        "AcceptEventAction",
        "ActionExecutionSpecification",
        "ActionInputPin",
        "Activity",
        "ActivityFinalNode",
        "ActivityParameterNode",
        "ActivityPartition",
        "Actor",
        "AddStructuralFeatureValueAction",
        "AddVariableValueAction",
        "AnyReceiveEvent",
        "Artifact",
        "Association",
        "AssociationClass",
        "BehaviorExecutionSpecification",
        "BroadcastSignalAction",
        "CallBehaviorAction",
        "CallEvent",
        "CallOperationAction",
        "CentralBufferNode",
        "ChangeEvent",
        "Class",
        "ClassifierTemplateParameter",
        "Clause",
        "ClearAssociationAction",
        "ClearStructuralFeatureAction",
        "ClearVariableAction",
        "Collaboration",
        "CollaborationUse",
        "CombinedFragment",
        "Comment",
        "CommunicationPath",
        "Component",
        "ComponentRealization",
        "ConditionalNode",
        "ConnectableElementTemplateParameter",
        "ConnectionPointReference",
        "Connector",
        "ConnectorEnd",
        "ConsiderIgnoreFragment",
        "Constraint",
        "Continuation",
        "ControlFlow",
        "CreateLinkAction",
        "CreateLinkObjectAction",
        "CreateObjectAction",
        "DataStoreNode",
        "DataType",
        "DecisionNode",
        "Dependency",
        "Deployment",
        "DeploymentSpecification",
        "DestroyLinkAction",
        "DestroyObjectAction",
        "DestructionOccurrenceSpecification",
        "Device",
        "Duration",
        "DurationConstraint",
        "DurationInterval",
        "DurationObservation",
        "ElementImport",
        "Enumeration",
        "EnumerationLiteral",
        "ExceptionHandler",
        "ExecutionEnvironment",
        "ExecutionOccurrenceSpecification",
        "ExpansionNode",
        "ExpansionRegion",
        "Expression",
        "Extend",
        "Extension",
        "ExtensionEnd",
        "ExtensionPoint",
        "FinalState",
        "FlowFinalNode",
        "ForkNode",
        "FunctionBehavior",
        "Gate",
        "GeneralOrdering",
        "Generalization",
        "GeneralizationSet",
        "Image",
        "Include",
        "InformationFlow",
        "InformationItem",
        "InitialNode",
        "InputPin",
        "InstanceSpecification",
        "InstanceValue",
        "Interaction",
        "InteractionConstraint",
        "InteractionOperand",
        "InteractionUse",
        "Interface",
        "InterfaceRealization",
        "InterruptibleActivityRegion",
        "Interval",
        "IntervalConstraint",
        "JoinNode",
        "Lifeline",
        "LinkEndCreationData",
        "LinkEndData",
        "LinkEndDestructionData",
        "LiteralBoolean",
        "LiteralInteger",
        "LiteralNull",
        "LiteralReal",
        "LiteralString",
        "LiteralUnlimitedNatural",
        "LoopNode",
        "Manifestation",
        "MergeNode",
        "Message",
        "MessageOccurrenceSpecification",
        "Model",
        "Node",
        "ObjectFlow",
        "OccurrenceSpecification",
        "OpaqueAction",
        "OpaqueBehavior",
        "OpaqueExpression",
        "Operation",
        "OperationTemplateParameter",
        "OutputPin",
        "Package",
        "PackageImport",
        "PackageMerge",
        "Parameter",
        "ParameterSet",
        "PartDecomposition",
        "Port",
        "PrimitiveType",
        "Profile",
        "ProfileApplication",
        "Property",
        "ProtocolConformance",
        "ProtocolStateMachine",
        "ProtocolTransition",
        "Pseudostate",
        "QualifierValue",
        "RaiseExceptionAction",
        "ReadExtentAction",
        "ReadIsClassifiedObjectAction",
        "ReadLinkAction",
        "ReadLinkObjectEndAction",
        "ReadLinkObjectEndQualifierAction",
        "ReadSelfAction",
        "ReadStructuralFeatureAction",
        "ReadVariableAction",
        "Realization",
        "Reception",
        "ReclassifyObjectAction",
        "RedefinableTemplateSignature",
        "ReduceAction",
        "Region",
        "RemoveStructuralFeatureValueAction",
        "RemoveVariableValueAction",
        "ReplyAction",
        "SendObjectAction",
        "SendSignalAction",
        "SequenceNode",
        "Signal",
        "SignalEvent",
        "Slot",
        "StartClassifierBehaviorAction",
        "StartObjectBehaviorAction",
        "State",
        "StateInvariant",
        "StateMachine",
        "Stereotype",
        "StringExpression",
        "StructuredActivityNode",
        "Substitution",
        "TemplateBinding",
        "TemplateParameter",
        "TemplateParameterSubstitution",
        "TemplateSignature",
        "TestIdentityAction",
        "TimeConstraint",
        "TimeEvent",
        "TimeExpression",
        "TimeInterval",
        "TimeObservation",
        "Transition",
        "Trigger",
        "UnmarshallAction",
        "Usage",
        "UseCase",
        "ValuePin",
        "ValueSpecificationAction",
        "Variable",
    ]
)


def unknown_type_message(kind: str) -> str:
    import difflib  # only for an unknown type: it costs start-up time

    close = difflib.get_close_matches(kind, UML_METACLASSES, n=1)
    hint = f" (did you mean uml:{close[0]}?)" if close else ""
    return f"unknown xmi:type uml:{kind}{hint}; the element is skipped"


def check_ids(model: UmlModel, ids: list[tuple[str, int]]) -> set[str]:
    """Report ids defined twice (R203); return the set of all ids."""
    known = {ident for ident, _ in ids}
    if len(known) == len(ids):  # the usual case: no line bookkeeping
        return known
    lines: dict[str, list[int]] = defaultdict(list)
    for ident, line in ids:
        lines[ident].append(line)
    for ident, where in lines.items():
        if len(where) > 1:
            where.sort()
            model.diagnostics.append(
                diagnostic(
                    "R203",
                    f"id {ident!r} is defined {len(where)} times (lines "
                    f"{', '.join(map(str, where[:10]))}{', ...' if len(where) > 10 else ''}); "
                    "ids must be unique: re-export the model",
                    file=model.file,
                    line=where[0],
                    xmi_id=ident,
                )
            )
    return set(lines)


def dangling(model: UmlModel, ident: str, what: str, line: int, element: str | None) -> None:
    model.diagnostics.append(
        diagnostic(
            "R202",
            f"{what} refers to id {ident!r}, which no element has; re-export the model or restore the element",
            file=model.file,
            line=line,
            element=element,
            xmi_id=ident,
        )
    )
