# SPDX-License-Identifier: LGPL-2.1-or-later
"""The face classes of a parting analysis's result: their keys, legend labels and
colours (FACE_CLASSES), and the class of each face read from the result properties.
FreeCAD-free (the result object is only read), so the view (gui/parting_view.py, which
paints from it) and the task panel (gui/parting_panel.py, whose legend lists from it)
both import it from here and pytest tests it."""

import json

from mfgeom import palette

# The face classes of the Result display mode: key -> (legend label, RGB).  The one
# table of the parting colours: face_colors paints from it and the task panel's legend
# (legend_entries) lists from it.  In the order the legend lists them.  The Mould
# colours differ by >= 10 CIELAB units under normal, protan and deutan vision (the
# least: core blue against zero-draft pink under protanopia, 10.3).
FACE_CLASSES = {
    # Mould
    "core": ("Core side (+d)", palette.CORE_SIDE),
    "cavity": ("Cavity side (-d)", palette.CAVITY_SIDE),
    "zero_draft": ("Zero draft (wall within the angular tolerance of d)",
                   palette.SETUP_COLORS[5]),                              # pink
    "insufficient_draft": ("Insufficient draft (below the draft angle)",
                           palette.SETUP_COLORS[2]),                      # sand
    "undercut": ("Undercut (not demouldable along +-d)", palette.UNDERCUT),  # indigo
    "shadowed": ("Shadowed (ray check: blocked by the part)",
                 palette.SETUP_COLORS[1]),                                # brown
    "no_direction": ("Undercut with no side-core direction", (0.0, 0.0, 0.0)),
    # Draft
    "positive": ("Positive draft (along +pull)", palette.CORE_SIDE),
    "negative": ("Negative draft (along -pull)", palette.CAVITY_SIDE),
    "insufficient": ("Insufficient draft", palette.SETUP_COLORS[5]),      # pink
    "straddle": ("Straddle (normals on both sides)", palette.SETUP_COLORS[2]),  # sand
    # NC3Axis (set-up k: "setup<k>", see class_color)
    "unresolved": ("Pocket no set-up reaches", palette.CAVITY_SIDE),
    # every mode
    "other": ("Not classified (parallel to d, or not analysed)", palette.SHAPE_GREY),
}


def class_label(key):
    """The legend text of a face class key (FACE_CLASSES, or "setup<k>")."""
    if key.startswith("setup"):
        return f"Set-up {key[5:]}"
    return FACE_CLASSES[key][0]


def class_color(key):
    """The RGB of a face class key (FACE_CLASSES, or "setup<k>": palette.setup_color(k))."""
    if key.startswith("setup"):
        return palette.setup_color(int(key[5:]))
    return FACE_CLASSES[key][1]


def face_classes(obj, nfaces):
    """One class key per face of the source's shape (Face1 first) from the result
    properties; later assignments win (a shadowed core face is "shadowed")."""
    keys = ["other"] * nfaces

    def mark(names, key):
        for name in names:
            if name.startswith("Face") and name[4:].isdigit() and 0 < int(name[4:]) <= nfaces:
                keys[int(name[4:]) - 1] = key
    if obj.Mode == "Draft":
        mark(getattr(obj, "PositiveDraftFaces", []), "positive")
        mark(getattr(obj, "NegativeDraftFaces", []), "negative")
        mark(obj.InsufficientDraftFaces, "insufficient")
        mark(getattr(obj, "StraddleFaces", []), "straddle")
    elif obj.Mode == "Mould":
        mark(obj.CoreFaces, "core")
        mark(obj.CavityFaces, "cavity")
        mark(obj.UncoveredFaces, "undercut")
        mark(obj.InsufficientDraftFaces, "insufficient_draft")
        mark(getattr(obj, "ZeroDraftFaces", []), "zero_draft")
        # the ray check found them blocked: undercuts the normals cannot see
        mark(getattr(obj, "ShadowedFaces", []), "shadowed")
        mark(obj.UnresolvedFaces, "no_direction")
    else:
        for k, entry in enumerate(obj.Setups, 1):
            mark(json.loads(entry)["faces"], f"setup{k}")
        mark(obj.UnresolvedFaces, "unresolved")
    return keys


def face_colors(obj, nfaces):
    """One RGB per face of the source's shape (Face1 first) from the result properties."""
    return [class_color(k) for k in face_classes(obj, nfaces)]


def legend_entries(obj, nfaces=None):
    """[(key, label, RGB)] of the face classes present in ``obj``'s result, in the
    table's order (set-ups in their order): what the task panel's legend shows."""
    if nfaces is None:
        source = getattr(obj, "Source", None)
        nfaces = len(source.Shape.Faces) if source is not None else 0
    present = set(face_classes(obj, nfaces))
    order = [k for k in FACE_CLASSES if k in present and k != "other"]
    order += sorted((k for k in present if k.startswith("setup")), key=lambda k: int(k[5:]))
    if "other" in present:
        order.append("other")
    return [(k, class_label(k), class_color(k)) for k in order]
