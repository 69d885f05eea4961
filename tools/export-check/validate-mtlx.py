#!/usr/bin/env python3
"""Validates a MaterialX document written by `clothbake export` with MaterialX's own library.

    .venv/bin/python tools/export-check/validate-mtlx.py FILE

Reads FILE with the standard data libraries (libraries/stdlib, pbrlib, bxdf, ...) imported,
so that the nodedef of `open_pbr_surface` (ND_open_pbr_surface_surfaceshader, in bxdf/)
resolves, then checks:
  - the file declares a MaterialX version of 1.39 or newer (open_pbr_surface's first);
  - Document.validate() passes;
  - there is at least one open_pbr_surface node, each one's nodedef resolves;
  - at least one surfacematerial has its surfaceshader input connected to an open_pbr_surface.
Prints the MaterialX version used, the problems found, and a one-line result.
Exit status: 0 valid, 1 invalid, 2 unreadable (missing file, XML that does not parse), 64 usage.
"""
import sys
import xml.etree.ElementTree as ET

import MaterialX as mx


def main(argv):
    if len(argv) != 2 or argv[1].startswith("-"):
        print("usage: validate-mtlx.py FILE", file=sys.stderr)
        return 64
    path = argv[1]
    print(f"MaterialX {mx.getVersionString()}: {path}")

    # The version the file declares: readFromXmlFile upgrades older documents in memory, so
    # read the attribute from the XML itself.
    try:
        root = ET.parse(path).getroot()
    except (OSError, ET.ParseError) as error:
        print(f"result: UNREADABLE ({error})")
        return 2
    declared = root.get("version", "")

    doc = mx.createDocument()
    try:
        mx.readFromXmlFile(doc, path)
    except Exception as error:  # mx.ExceptionFileMissing, mx.ExceptionParseError, ...
        print(f"result: UNREADABLE ({type(error).__name__}: {error})")
        return 2

    stdlib = mx.createDocument()
    search_path = mx.getDefaultDataSearchPath()
    mx.loadLibraries(mx.getDefaultDataLibraryFolders(), search_path, stdlib)
    doc.importLibrary(stdlib)

    problems = []
    if root.tag != "materialx":
        problems.append(f"root element is <{root.tag}>, not <materialx>")
    try:
        major, minor = (int(part) for part in declared.split(".")[:2])
        if (major, minor) < (1, 39):
            problems.append(f'declares version "{declared}", open_pbr_surface needs 1.39')
    except ValueError:
        problems.append(f'declares no usable version ("{declared}")')

    valid, message = doc.validate()
    if not valid:
        problems.extend(f"validate(): {line}" for line in message.strip().splitlines())

    # Elements that came from the imported libraries carry the library's source URI.
    own = [n for n in doc.traverseTree() if n.isA(mx.Node) and not n.hasSourceUri()]
    shaders = [n for n in own if n.getCategory() == "open_pbr_surface"]
    if not shaders:
        problems.append("no open_pbr_surface node")
    for shader in shaders:
        nodedef = shader.getNodeDef()
        if nodedef is None:
            problems.append(f"{shader.getNamePath()}: no nodedef resolves for open_pbr_surface")
        if shader.getType() != "surfaceshader":
            problems.append(f"{shader.getNamePath()}: type {shader.getType()}, not surfaceshader")

    materials = [n for n in own if n.getCategory() == "surfacematerial"]
    connected = []
    for material in materials:
        surface = material.getInput("surfaceshader")
        node = surface.getConnectedNode() if surface is not None else None
        if node is not None and node.getCategory() == "open_pbr_surface":
            connected.append(f"{material.getName()} <- {node.getName()}")
    if not materials:
        problems.append("no surfacematerial node")
    elif not connected:
        problems.append("no surfacematerial has its surfaceshader connected to an open_pbr_surface")

    for problem in problems:
        print(f"problem: {problem}")
    if problems:
        plural = "s" if len(problems) > 1 else ""
        print(f"result: INVALID ({len(problems)} problem{plural}; document version {declared or '?'})")
        return 1
    nodedef = shaders[0].getNodeDef().getName()
    print(
        f"result: VALID (document version {declared}; {len(shaders)} open_pbr_surface via "
        f"{nodedef}; material {', '.join(connected)})"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
