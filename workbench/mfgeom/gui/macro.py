# SPDX-License-Identifier: LGPL-2.1-or-later
"""Runs the workbench's make functions through FreeCAD's Python console (Gui.doCommand),
so the user sees each call in the console and a macro recording replays it.

A command or task panel calls ``echo_make_*`` (or ``make_point_classification`` here)
instead of the make function: the call is written out as Python source that names
documents and objects by their internal names (``App.getDocument("X").getObject("Box")``),
run in the console's namespace, and the new object is returned.  An exception of the make
function (e.g. mfgeom.errors.InputError) reaches the caller unchanged (Gui.doCommand
re-raises it) and the document is left as it was.  ``app_set``, ``gui_set`` and
``recompute`` echo property edits the same way.
"""

import FreeCADGui


def _text(value):
    return repr(str(value))  # a Python string literal


def document_expr(doc):
    """Python source that finds ``doc`` in a macro: ``App.getDocument("Name")``."""
    return f"App.getDocument({_text(doc.Name)})"


def object_expr(obj):
    """Python source that finds ``obj``: ``App.getDocument("D").getObject("Name")``."""
    return f"{document_expr(obj.Document)}.getObject({_text(obj.Name)})"


def _ref_expr(obj, subs):
    if isinstance(subs, str):
        return f"({object_expr(obj)}, {_text(subs)})"
    return f"({object_expr(obj)}, [{', '.join(_text(s) for s in subs)}])"


def echo_make(doc, call, type_name, what):
    """Runs ``call`` (the Python source of a make function's call) through the console,
    so the Report view and a recorded macro show it, and returns the one object of proxy
    type ``type_name`` it added to ``doc``; RuntimeError otherwise (``what``: the plural
    noun for the message)."""
    before = {o.Name for o in doc.Objects}
    FreeCADGui.doCommand("import mfgeom")
    FreeCADGui.doCommand(call)
    new = [o for o in doc.Objects if o.Name not in before
           and getattr(getattr(o, "Proxy", None), "Type", "") == type_name]
    if len(new) != 1:
        raise RuntimeError(f"'{call}' created {len(new)} {what}, expected 1")
    return new[0]


def point_classification_call(doc, face_ref, points_ref, tolerance, strict=True, name=None):
    """Python source of the ``mfgeom.make_point_classification`` call for these inputs.

    ``face_ref``: ``(obj, "FaceN")``; ``points_ref``: an object or ``(obj, [subnames])``
    (an empty list: the whole object); ``tolerance`` in mm."""
    face_obj, face_sub = face_ref
    if isinstance(points_ref, (tuple, list)):
        src_obj, src_subs = points_ref
        src = _ref_expr(src_obj, list(src_subs)) if src_subs else object_expr(src_obj)
    else:
        src = object_expr(points_ref)
    # The tolerance with its unit, as the make function accepts it and a reader expects.
    args = [document_expr(doc), _ref_expr(face_obj, face_sub), src,
            _text(f"{float(tolerance)!r} mm"), f"strict={bool(strict)}"]
    if name:
        args.append(f"name={_text(name)}")
    return f"mfgeom.make_point_classification({', '.join(args)})"


def echo_make_point_classification(doc, face_ref, points_ref, tolerance, strict=True,
                                   name=None):
    """Create a point classification through the Python console and return it.

    Same arguments as :func:`point_classification_call` (``tolerance`` in mm, already
    checked by the caller or left to the make function to reject)."""
    call = point_classification_call(doc, face_ref, points_ref, tolerance, strict, name)
    return echo_make(doc, call, "Mfgeom::PointClassification", "point classifications")


def make_point_classification(face_ref, points_ref, tolerance, strict=True, name=None):
    """:func:`echo_make_point_classification` in the face's document."""
    return echo_make_point_classification(face_ref[0].Document, face_ref, points_ref,
                                          tolerance, strict, name)


def parting_analysis_call(doc, source, mode="Mould", draft_angle=0.0, weighting="Count",
                          all_faces=False, faces=None, name=None, pull_direction=None):
    """Python source of the ``mfgeom.make_parting_analysis`` call for these inputs
    (``draft_angle`` in degrees, written with its unit; ``pull_direction`` 3 numbers)."""
    args = [document_expr(doc), object_expr(source), f"mode={_text(mode)}",
            f"draft_angle={_text(f'{float(draft_angle)!r} deg')}",
            f"weighting={_text(weighting)}"]
    if all_faces:
        args.append("all_faces=True")
    if faces:
        args.append(f"faces=[{', '.join(_text(f) for f in faces)}]")
    if name:
        args.append(f"name={_text(name)}")
    if pull_direction is not None:
        args.append("pull_direction=(" + ", ".join(repr(float(c)) for c in pull_direction)
                    + ")")
    return f"mfgeom.make_parting_analysis({', '.join(args)})"


def echo_make_parting_analysis(doc, source, mode="Mould", draft_angle=0.0, weighting="Count",
                               all_faces=False, faces=None, name=None, pull_direction=None):
    """Create a parting analysis through the Python console and return it (arguments as
    :func:`parting_analysis_call`)."""
    call = parting_analysis_call(doc, source, mode, draft_angle, weighting, all_faces,
                                 faces, name, pull_direction)
    return echo_make(doc, call, "Mfgeom::PartingAnalysis", "parting analyses")


def app_set(obj, prop, value):
    """``obj.prop = value`` through the console (recorded in macros)."""
    FreeCADGui.doCommand(f"{object_expr(obj)}.{prop} = {value!r}")


def gui_set(obj, prop, value):
    """``obj.ViewObject.prop = value`` through the console (a GUI-only line)."""
    FreeCADGui.doCommandGui(f"Gui.getDocument({_text(obj.Document.Name)})"
                            f".getObject({_text(obj.Name)}).{prop} = {value!r}")


def recompute(obj):
    """Recompute ``obj``'s document through the console."""
    FreeCADGui.doCommand(f"{document_expr(obj.Document)}.recompute()")
