# SPDX-License-Identifier: LGPL-2.1-or-later
"""The mfgeom package: the ctypes binding (core) and the FreeCAD workbench code.

Layers (each feature adds one module per layer):

* FreeCAD-free, importable from plain python3 + numpy: ``core`` (the ctypes binding,
  library loaded on first use), ``cli``, ``errors`` (one exception base class),
  ``names`` (class and kind codes), ``palette`` (result colours), ``paths``;
* ``mfgeom.app``: FreeCAD App layer (feature proxies, reference resolution, geometry
  that needs Part), works in freecadcmd;
* ``mfgeom.gui``: commands, view providers, task panels (only when FreeCAD.GuiUp).

Importing the package must work in plain python3 without FreeCAD (users of
``mfgeom.core`` do that), so nothing here imports FreeCAD or loads the C library;
the FreeCAD-facing entry points import their modules when called.
"""

import functools

__version__ = "0.1.0"


def needs_library(make):
    """Decorator of every public ``make_*`` function: loads libmfgeom first, so a missing
    library raises :class:`mfgeom.errors.LibraryError` (an ImportError, saying where it
    was looked for and how to build it) before the document is touched."""
    @functools.wraps(make)
    def checked(*args, **kwargs):
        from mfgeom import core
        core.load()
        return make(*args, **kwargs)
    return checked


@needs_library
def make_point_classification(doc, face_ref, points_ref, tolerance=None,
                              name="PointClassification", strict=True):
    """Create a parametric point classification of points against a face in ``doc``.

    ``face_ref`` is ``(obj, "FaceN")``; ``points_ref`` is an object (Points, Mesh,
    Sketch or any Part shape: its vertices) or ``(obj, ["Vertex1", ...])``.
    ``tolerance`` is in mm, a length Quantity or a string such as "0.01 mm" (default:
    the preference DefaultTolerance).  ``strict``: points farther than the tolerance
    from the face's surface are OUT (False: classified by their projection onto it).
    Raises ValueError/TypeError on bad input and mfgeom.errors.LibraryError (an
    ImportError) without the C library, and creates nothing in those cases.
    See :func:`mfgeom.app.pointclass.make_point_classification`.
    """
    from mfgeom.app.pointclass import make_point_classification as _make
    return _make(doc, face_ref, points_ref, tolerance=tolerance, name=name, strict=strict)


@needs_library
def make_parting_analysis(doc, source, mode="Mould", draft_angle=0.0, weighting="Count",
                          all_faces=False, name="PartingAnalysis", faces=None,
                          pull_direction=None):
    """Create a parametric mould parting ("Mould"), 3-axis set-up ("NC3Axis") or draft
    analysis ("Draft", along ``pull_direction``: a vector, a face, a straight edge or
    (object, "FaceN")) of ``source`` (or of its ``faces``, e.g. ["Face3"]) in ``doc``;
    ``draft_angle`` in degrees.  See
    :func:`mfgeom.app.parting_feature.make_parting_analysis`."""
    from mfgeom.app.parting_feature import make_parting_analysis as _make
    return _make(doc, source, mode=mode, draft_angle=draft_angle, weighting=weighting,
                 all_faces=all_faces, name=name, faces=faces, pull_direction=pull_direction)


def check_clearance(doc_or_sweep, others=None, tolerance=None):
    """Clearance check of issue 8: for each solid of ``others`` the interference volume
    with the swept volume (0: none) and the minimum distance to it.

    ``doc_or_sweep``: the sweep object (the sweep feature, or any object with a solid
    Shape or a closed Mesh) or a document holding one sweep feature; ``others``: an object
    or a list of them (default: every other solid of the document except the sweep's
    source).  ``tolerance``: mm or a length Quantity (default: the sweep's own Tolerance,
    else the preference DefaultTolerance).  Returns a list of
    :class:`mfgeom.app.clearance.ClearanceResult`; non-solids get status "invalid" and a
    message.  Changes nothing in the document.
    See :func:`mfgeom.app.clearance.check_clearance`."""
    from mfgeom.app import clearance
    sweep, objs = clearance.resolve(doc_or_sweep, others)
    return clearance.check_clearance(sweep, objs, tolerance=tolerance)


@needs_library
def make_rotational_sweep(doc, source, axis_point=(0.0, 0.0, 0.0), axis_dir=(0.0, 0.0, 1.0),
                          angle_deg=90.0, tolerance=None, **kwargs):
    """Create the parametric volume swept by ``source`` (a solid) turning by 0 ..
    ``angle_deg`` about the axis through ``axis_point`` along ``axis_dir`` (global),
    within ``tolerance`` mm (None: a thousandth of the part's size, rounded down to 1, 2
    or 5 x 10^k).  Keywords: ``deflection`` (mm, curved faces; None: as the tolerance),
    ``representation`` ("Mesh" or "Solid"), ``axis`` (an edge ``(obj, "EdgeN")``, datum
    line or origin axis instead of point and direction), ``reverse``, ``name``.
    See :func:`mfgeom.app.sweep_feature.make_rotational_sweep`."""
    from mfgeom.app.sweep_feature import make_rotational_sweep as _make
    return _make(doc, source, axis_point, axis_dir, angle_deg, tolerance, **kwargs)


@needs_library
def make_medial_axis(doc, face_ref, tolerance=0.01, name="MedialAxis"):
    """Create the parametric medial axis of the planar face ``face_ref`` = ``(obj,
    "FaceN")`` in ``doc``: wires on the face with the clearance radius along them,
    within ``tolerance`` (mm, a length Quantity or "0.01 mm").
    See :func:`mfgeom.app.medial_axis_feature.make_medial_axis`."""
    from mfgeom.app.medial_axis_feature import make_medial_axis as _make
    return _make(doc, face_ref, tolerance, name=name)


@needs_library
def make_medial_surface(doc, source, tolerance=None, major_only=True, **kwargs):
    """Create the parametric medial surface of the solid ``source`` in ``doc``: sheets
    coloured by thickness (2 x radius), seams as wires, junctions as vertices.
    ``tolerance``: mm (default None: 0.5 % of the bounding-box diagonal); ``major_only``:
    the mid-surface part only.  Keywords: ``deflection`` (mm, curved faces), ``name``.
    See :func:`mfgeom.app.medial_surface_feature.make_medial_surface`."""
    from mfgeom.app.medial_surface_feature import make_medial_surface as _make
    return _make(doc, source, tolerance, major_only, **kwargs)


@needs_library
def make_mid_surface(doc, source, csv_path=None, tolerance=None, **kwargs):
    """Create the FEM mid-surface (a shell) with the local thickness of a thin-walled
    part: ``source`` is a solid (its major medial surface is made first) or a medial
    surface feature; ``csv_path``: write the points and their thickness there.
    Keywords: ``bins`` (thickness histogram), ``deflection``, ``name``.
    See :func:`mfgeom.app.mid_surface_feature.make_mid_surface`."""
    from mfgeom.app.mid_surface_feature import make_mid_surface as _make
    return _make(doc, source, csv_path, tolerance, **kwargs)


@needs_library
def make_parting_line(doc, analysis, zero_draft_side="Cavity", name="PartingLine"):
    """Create the parting line of a Mould-mode parting ``analysis`` (issue 21): a
    ``PartingLine`` whose Shape holds the closed loops as wires (outer loops, inner loops
    of through-holes, then the side cores' shut-off loops).  Zero-draft faces touching
    both sides go to ``zero_draft_side`` ("Cavity": the line runs along their +d edge).
    See :func:`mfgeom.app.mould_feature.make_parting_line`."""
    from mfgeom.app.mould_feature import make_parting_line as _make
    return _make(doc, analysis, zero_draft_side=zero_draft_side, name=name)


@needs_library
def make_parting_surface(doc, parting_line, margin=10.0, name="PartingSurface"):
    """Create the parting surfaces (outer loops out to a box ``margin`` mm beyond the
    part) and shut-off surfaces (inner loops) of ``parting_line``.  See
    :func:`mfgeom.app.mould_feature.make_parting_surface`."""
    from mfgeom.app.mould_feature import make_parting_surface as _make
    return _make(doc, parting_line, margin=margin, name=name)


@needs_library
def make_mould_blocks(doc, analysis, margin=10.0, zero_draft_side="Cavity", name="MouldBlocks"):
    """Create the core (+d), cavity (-d) and side-core inserts of a Mould-mode parting
    ``analysis`` in a block ``margin`` mm beyond the part (``MouldBlocks`` with ``Core``,
    ``Cavity``, ``Inserts`` (a compound, ``Inserts.Solids``) and ``Checks``), making the
    parting line and surface it needs.  See
    :func:`mfgeom.app.mould_feature.make_mould_blocks`."""
    from mfgeom.app.mould_feature import make_mould_blocks as _make
    return _make(doc, analysis, margin=margin, zero_draft_side=zero_draft_side, name=name)


@needs_library
def make_thickness_analysis(doc, source, min_thickness, max_thickness, **kwargs):
    """Create the wall-thickness analysis of ``source`` (``ThicknessAnalysis`` with
    ``MinThickness``, ``MaxThickness`` (mm, the thin / thick thresholds), per-sample
    ``VertexThickness`` and per-face ``FaceMin/Max/MeanThickness``): the diameter of the
    maximal inscribed ball touching each point, from the medial surface.  Keywords:
    ``tolerance``, ``deflection``, ``sample_spacing``, ``min_angle`` (degrees), ``name``.  See
    :func:`mfgeom.app.thickness_feature.make_thickness_analysis`."""
    from mfgeom.app.thickness_feature import make_thickness_analysis as _make
    return _make(doc, source, min_thickness, max_thickness, **kwargs)
