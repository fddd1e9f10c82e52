"""modelDescription.xml of the self-contained FMU, FMI 2.0 or FMI 3.0, from the unit's variables.

Both versions carry the same variables with the same value references (the index in the unit's
list, as in the lean FMU that pythonfmu describes; FMI 3.0 adds its independent variable ``time``
after them): Real/Float64, Integer/Int32, Boolean.  Every
output is ``initial="exact"`` with the machine's power-on value as start value, so the model
structure lists the outputs and no initial unknowns.  Co-simulation only, with a fixed
communication step: no event mode, no clocks (FMPy, the reference host here, runs FMI 3.0
co-simulation without them), no FMU state.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass

from fmu.unit import Causality, Kind, NcUnit, Variability

TIME = "time"
GENERATION_TOOL = "VC harness (vc fmu export)"
LOG_CATEGORIES = {
    "logStatusWarning": "messages with status warning",
    "logStatusError": "errors: a value or step refused, with the reason",
    "logStatusFatal": "what ended the instance, with the reason",
    "logAll": "all messages",
}
_TYPE_NAMES = {2: {Kind.REAL: "Real", Kind.INTEGER: "Integer", Kind.BOOLEAN: "Boolean"},
               3: {Kind.REAL: "Float64", Kind.INTEGER: "Int32", Kind.BOOLEAN: "Boolean"}}


@dataclass(frozen=True, slots=True)
class Identity:
    model_identifier: str
    token: str  # FMI 2.0 guid, FMI 3.0 instantiationToken
    model_name: str
    description: str
    stop_time_s: float


def start_text(value: float | int | bool) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    return repr(float(value))


def model_description(unit: NcUnit, fmi_version: int, identity: Identity) -> bytes:
    """The XML document for ``fmi_version`` (2 or 3) of the unit as it stands at power-on."""
    root = ET.Element("fmiModelDescription", {
        "fmiVersion": f"{fmi_version}.0",
        "modelName": identity.model_name,
        "guid" if fmi_version == 2 else "instantiationToken": identity.token,
        "description": identity.description,
        "generationTool": GENERATION_TOOL,
        "variableNamingConvention": "structured",
    })
    common = {"modelIdentifier": identity.model_identifier, "canHandleVariableCommunicationStepSize": "true",
              "canBeInstantiatedOnlyOncePerProcess": "false"}
    if fmi_version == 2:
        ET.SubElement(root, "CoSimulation", {**common, "needsExecutionTool": "false", "canInterpolateInputs": "false",
                                             "canGetAndSetFMUstate": "false", "canSerializeFMUstate": "false"})
    else:
        ET.SubElement(root, "CoSimulation", {**common, "canGetAndSetFMUState": "false", "canSerializeFMUState": "false",
                                             "hasEventMode": "false", "providesIntermediateUpdate": "false"})
    categories = ET.SubElement(root, "LogCategories")
    for name, text in LOG_CATEGORIES.items():
        ET.SubElement(categories, "Category", {"name": name, "description": text})
    ET.SubElement(root, "DefaultExperiment", {"startTime": "0.0", "stopTime": repr(identity.stop_time_s),
                                               "stepSize": repr(unit.plc_cycle_s)})
    variables = ET.SubElement(root, "ModelVariables")
    outputs: list[int] = []
    for index, variable in enumerate(unit.variables):
        attributes = {"name": variable.name, "valueReference": str(index), "description": variable.description,
                      "causality": variable.causality.value, "variability": variable.variability.value}
        if variable.causality is Causality.OUTPUT:
            outputs.append(index)
        if variable.causality is not Causality.INPUT:
            attributes["initial"] = "exact"
        start = start_text(unit.get(index))
        type_name = _TYPE_NAMES[fmi_version][variable.kind]
        if fmi_version == 2:
            element = ET.SubElement(variables, "ScalarVariable", attributes)
            ET.SubElement(element, type_name, {"start": start})
        else:
            if variable.variability is Variability.CONTINUOUS and variable.kind is not Kind.REAL:
                raise AssertionError(f"{variable.name}: only a Float64 can be continuous")
            ET.SubElement(variables, type_name, {**attributes, "start": start})
    if fmi_version == 3:  # FMI 3.0 wants its independent variable declared; its reference follows the others
        ET.SubElement(variables, "Float64", {"name": TIME, "valueReference": str(len(unit.variables)),
                                             "description": "simulation time, s", "causality": "independent",
                                             "variability": "continuous"})
    structure = ET.SubElement(root, "ModelStructure")
    if fmi_version == 2:
        listed = ET.SubElement(structure, "Outputs")
        for index in outputs:
            ET.SubElement(listed, "Unknown", {"index": str(index + 1)})  # 1-based position in ModelVariables
    else:
        for index in outputs:
            ET.SubElement(structure, "Output", {"valueReference": str(index)})
    ET.indent(root, space="  ")
    document: bytes = ET.tostring(root, encoding="UTF-8", xml_declaration=True)
    return document + b"\n"
