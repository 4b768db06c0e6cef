# SPDX-License-Identifier: LGPL-2.1-or-later
"""The parametric mould features of issue 21 on top of a Mould-mode PartingAnalysis:
``PartingLine`` (the loops as wires), ``PartingSurface`` (parting and shut-off
surfaces) and ``MouldBlocks`` (core, cavity and side-core inserts, checked).  The
geometry is :mod:`mfgeom.app.mould`'s; here are the proxies, the make functions and
the cache that lets the surface and the blocks reuse the line of the same analysis.

Chain: PartingAnalysis -> PartingLine -> PartingSurface -> MouldBlocks, each linking the
one before; a change of the part or of the analysis recomputes them in that order.
"""

import json
import time

import FreeCAD
import Part

from mfgeom.app.feature_base import VERSION_PROPERTY, add_properties, FeatureProxy
from mfgeom.app.mould import MouldError, MouldInputError, ZERO_DRAFT_SIDES

VERSION = 1
DEFAULT_MARGIN = 10.0   # mm: block margin around the part, and the parting surfaces' reach


def _length(value, what):
    """mm from a number, a length Quantity or a string such as "5 mm" (the medial axis'
    reader), a MouldInputError saying what is wrong."""
    from mfgeom.app.medial_axis_feature import length_value
    return length_value(value, what, MouldInputError)


def _analysis_inputs(analysis):
    """(shape, direction, side cores, tol) of a computed Mould analysis object; raises
    MouldInputError / MouldError saying what is missing.  Its unresolved faces are not
    refused here (see mfgeom.app.mould.undercut_hint)."""
    from mfgeom.app import gauss_map
    if analysis is None or getattr(getattr(analysis, "Proxy", None), "Type", "") != \
            "Mfgeom::PartingAnalysis":
        raise MouldInputError("a mould feature needs a parting analysis (Mould mode)")
    if analysis.Mode not in ("Mould", "Draft"):
        raise MouldInputError(f"'{analysis.Label}' is a {analysis.Mode} analysis; the mould "
                              "needs one in Mould mode (or a Draft analysis along the pull "
                              "direction you chose)")
    if list(analysis.Faces):
        raise MouldInputError(f"'{analysis.Label}' analyses only some faces; the mould needs "
                              "the whole part (empty Faces)")
    if analysis.Source is None:
        raise MouldInputError(f"'{analysis.Label}' has no source")
    if analysis.Direction.Length == 0:
        raise MouldError(f"'{analysis.Label}' found no parting direction (a part of curved "
                         "faces only: make a Draft analysis along the direction you want)")
    side_cores = []
    for text in (analysis.SideCores if analysis.Mode == "Mould" else []):
        entry = json.loads(text)
        side_cores.append((entry["direction"], entry["faces"]))
    shape = gauss_map.shape_of(analysis.Source)
    d = analysis.Direction
    return shape, (d.x, d.y, d.z), side_cores, float(analysis.AngularTolerance)


def _line_key(line_obj):
    a = line_obj.Analysis
    src = a.Source
    d = a.Direction
    return (a.Name, (d.x, d.y, d.z), tuple(a.SideCores), tuple(a.UnresolvedFaces),
            src.Name if src else None, src.Shape.hashCode() if src else None,
            str(src.getGlobalPlacement() if src else None), line_obj.ZeroDraftSide,
            float(a.AngularTolerance))


def line_of(line_obj):
    """The :class:`mfgeom.app.mould.PartingLine` of a PartingLine object: the proxy's
    last one while its inputs are unchanged, else computed (touching no property)."""
    from mfgeom.app import mould
    key = _line_key(line_obj)
    last = getattr(line_obj.Proxy, "last", None)
    if last is None or last[0] != key:
        shape, d, side_cores, tol = _analysis_inputs(line_obj.Analysis)
        with mould.undercut_hint(list(line_obj.Analysis.UnresolvedFaces)):
            line = mould.parting_line(shape, d, side_cores, line_obj.ZeroDraftSide, tol)
        last = (key, line)
        line_obj.Proxy.last = last
    return last[1]


class PartingLine(FeatureProxy):
    """App proxy: the parting line of a Mould analysis (Shape: the loops as wires)."""

    TYPE = "Mfgeom::PartingLine"
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.mould_view.ViewProviderPartingLine"

    def _set_defaults(self, obj):
        obj.ZeroDraftSide = list(ZERO_DRAFT_SIDES)

    @staticmethod
    def _add_properties(obj):
        add_properties(obj, [
            VERSION_PROPERTY,
            ("App::PropertyLink", "Analysis", "Input", "The parting analysis (Mould mode)",
             False),
            ("App::PropertyEnumeration", "ZeroDraftSide", "Input",
             "Zero-draft faces touching both sides go to: Cavity (the line runs along "
             "their +d edge, as high as possible) or Core (their -d edge)", False),
            ("App::PropertyInteger", "LoopCount", "Result", "Parting loops", True),
            ("App::PropertyStringList", "Loops", "Result",
             "Per loop (the Shape's wires in order): outer / inner (a through-hole, "
             "filled by a shut-off surface), planar / non-planar, its length", True),
            ("App::PropertyStringList", "ShutOffLoops", "Result",
             "Per side core: its shut-off loops (the last wires of the Shape)", True),
            ("App::PropertyStringList", "SplitFaces", "Result",
             "Faces of the source split along their silhouette n.d = 0", True),
        ])

    def _execute(self, obj):
        t0 = time.perf_counter()
        self.last = None
        line = line_of(obj)
        wires = list(line.loops) + [w for ws in line.shutoff_loops for w in ws]
        obj.Shape = Part.makeCompound(wires) if wires else Part.Shape()
        obj.LoopCount = len(line.loops)
        obj.Loops = [f"{'outer' if o else 'inner'}, {'planar' if p else 'non-planar'}, "
                     f"{w.Length:.6g} mm" for w, o, p in zip(line.loops, line.outer, line.planar)]
        obj.ShutOffLoops = [f"side core {k + 1}: {len(ws)} loop(s)"
                            for k, ws in enumerate(line.shutoff_loops)]
        obj.SplitFaces = list(line.split_faces)
        FreeCAD.Console.PrintLog(f"mfgeom: {obj.Label}: {len(line.loops)} loops "
                                 f"({1e3 * (time.perf_counter() - t0):.1f} ms)\n")

    def _restored(self):
        self.last = None


class PartingSurface(FeatureProxy):
    """App proxy: parting surfaces (outer loops) and shut-off surfaces (inner loops)."""

    TYPE = "Mfgeom::PartingSurface"
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.mould_view.ViewProviderPartingSurface"

    def _set_defaults(self, obj):
        obj.Margin = DEFAULT_MARGIN

    @staticmethod
    def _add_properties(obj):
        add_properties(obj, [
            VERSION_PROPERTY,
            ("App::PropertyLink", "PartingLine", "Input", "The parting line", False),
            ("App::PropertyLength", "Margin", "Input",
             "How far the surfaces reach beyond the part (the mould block's margin)", False),
            ("App::PropertyInteger", "PartingSurfaceCount", "Result",
             "Parting surfaces (one per outer loop; first in the Shape)", True),
            ("App::PropertyInteger", "ShutOffCount", "Result",
             "Shut-off surfaces (one per inner loop; last in the Shape)", True),
        ])

    def _execute(self, obj):
        from mfgeom.app import mould
        if obj.PartingLine is None:
            raise MouldInputError("no parting line; set the PartingLine property")
        line = line_of(obj.PartingLine)
        block = mould.mould_block(line.shape, line.direction, obj.Margin.Value)
        parting, shutoff = mould.parting_surfaces(line, block, obj.PartingLine.ZeroDraftSide)
        obj.Shape = Part.makeCompound(parting + shutoff)
        obj.PartingSurfaceCount = len(parting)
        obj.ShutOffCount = len(shutoff)


class MouldBlocks(FeatureProxy):
    """App proxy: core, cavity and side-core inserts, checked (mfgeom.app.mould)."""

    TYPE = "Mfgeom::MouldBlocks"
    VERSION = VERSION
    VIEW_PROVIDER = "mfgeom.gui.mould_view.ViewProviderMouldBlocks"

    def _set_defaults(self, obj):
        obj.Margin = DEFAULT_MARGIN

    @staticmethod
    def _add_properties(obj):
        add_properties(obj, [
            VERSION_PROPERTY,
            ("App::PropertyLink", "PartingSurface", "Input",
             "The parting surface (its line and analysis give the part and direction)",
             False),
            ("App::PropertyLength", "Margin", "Input",
             "The block's margin around the part (mm)", False),
            ("Part::PropertyPartShape", "Core", "Result", "The core (+d side), a solid", True),
            ("Part::PropertyPartShape", "Cavity", "Result", "The cavity (-d side), a solid",
             True),
            ("Part::PropertyPartShape", "Inserts", "Result",
             "The side-core inserts, one solid each (a compound: Inserts.Solids)", True),
            ("App::PropertyVector", "Direction", "Result", "Parting direction (core +d)",
             True),
            ("App::PropertyFloatList", "Volumes", "Result",
             "mm^3: block, part, core, cavity, inserts", True),
            ("App::PropertyStringList", "Checks", "Result",
             "The checks (volumes, overlap, validity, demoulding), one line each", True),
        ])

    def _execute(self, obj):
        from mfgeom.app import mould
        if obj.PartingSurface is None or obj.PartingSurface.PartingLine is None:
            raise MouldInputError("no parting surface; set the PartingSurface property")
        line_obj = obj.PartingSurface.PartingLine
        line = line_of(line_obj)
        t0 = time.perf_counter()
        with mould.undercut_hint(list(line_obj.Analysis.UnresolvedFaces)):
            result = mould.mould_blocks(line, obj.Margin.Value, line_obj.ZeroDraftSide,
                                        float(line_obj.Analysis.AngularTolerance))
        obj.Core = result.core
        obj.Cavity = result.cavity
        obj.Inserts = Part.makeCompound(result.inserts) if result.inserts else Part.Shape()
        obj.Shape = Part.makeCompound([result.core, result.cavity] + list(result.inserts))
        obj.Direction = FreeCAD.Vector(*[float(c) for c in line.direction])
        obj.Volumes = [result.block.solid.Volume, line.shape.Volume, result.core.Volume,
                       result.cavity.Volume] + [s.Volume for s in result.inserts]
        obj.Checks = [f"{k}: {'ok' if v['ok'] else 'FAILED'}" for k, v in result.checks.items()]
        FreeCAD.Console.PrintLog(f"mfgeom: {obj.Label}: core, cavity and "
                                 f"{len(result.inserts)} inserts in "
                                 f"{time.perf_counter() - t0:.2f} s\n")


def _check_doc_obj(doc, obj, what):
    if doc is None or not hasattr(doc, "addObject"):
        raise MouldInputError("no document given")
    if obj is None or getattr(obj, "Document", None) is not doc:
        raise MouldInputError(f"the {what} must be an object of this document")


def make_parting_line(doc, analysis, zero_draft_side="Cavity", name="PartingLine"):
    """Create the parting line of ``analysis`` (a Mould-mode PartingAnalysis) in ``doc``:
    a PartingLine whose Shape holds the loops as wires (then the side cores' shut-off
    loops).  ``zero_draft_side``: "Cavity" or "Core" (see mfgeom.app.mould)."""
    _check_doc_obj(doc, analysis, "analysis")
    _analysis_inputs(analysis)   # says what is wrong before anything is created
    if zero_draft_side not in ZERO_DRAFT_SIDES:
        raise MouldInputError(f"zero_draft_side must be one of {ZERO_DRAFT_SIDES}")
    return PartingLine.make(doc, name, {
        "Label": f"Parting line of {analysis.Source.Label}", "Analysis": analysis,
        "ZeroDraftSide": zero_draft_side}, "parting line", MouldError)


def make_parting_surface(doc, parting_line, margin=DEFAULT_MARGIN, name="PartingSurface"):
    """Create the parting and shut-off surfaces of ``parting_line`` reaching ``margin``
    (mm or a length) beyond the part."""
    _check_doc_obj(doc, parting_line, "parting line")
    if getattr(getattr(parting_line, "Proxy", None), "Type", "") != PartingLine.TYPE:
        raise MouldInputError(f"'{parting_line.Label}' is not a parting line")
    margin = _length(margin, "the margin")
    return PartingSurface.make(doc, name, {
        "Label": f"Parting surface of {parting_line.Analysis.Source.Label}",
        "PartingLine": parting_line, "Margin": margin}, "parting surface", MouldError)


def make_mould_blocks(doc, analysis, margin=DEFAULT_MARGIN, zero_draft_side="Cavity",
                      name="MouldBlocks"):
    """Create core, cavity and side-core inserts for ``analysis`` (Mould mode) in a block
    ``margin`` beyond the part, with the PartingLine and PartingSurface they need (made
    here unless ``analysis`` already has them).  Nothing is left half-made on a failure."""
    _check_doc_obj(doc, analysis, "analysis")
    _analysis_inputs(analysis)
    margin = _length(margin, "the margin")
    made = []
    try:
        line = next((o for o in analysis.InList
                     if getattr(getattr(o, "Proxy", None), "Type", "") == PartingLine.TYPE
                     and o.ZeroDraftSide == zero_draft_side), None)
        if line is None:
            line = make_parting_line(doc, analysis, zero_draft_side)
            made.append(line)
        surface = next((o for o in line.InList
                        if getattr(getattr(o, "Proxy", None), "Type", "") ==
                        PartingSurface.TYPE and abs(o.Margin.Value - margin) < 1e-12), None)
        if surface is None:
            surface = make_parting_surface(doc, line, margin)
            made.append(surface)
        return MouldBlocks.make(doc, name, {
            "Label": f"Mould of {analysis.Source.Label}", "PartingSurface": surface,
            "Margin": margin}, "mould blocks", MouldError)
    except Exception:
        for obj in reversed(made):
            doc.removeObject(obj.Name)
        raise
