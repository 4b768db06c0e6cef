# SPDX-License-Identifier: LGPL-2.1-or-later
"""Turns document references (face links, point sources, GUI selections) into geometry.

Every function raises ``InputError`` (a ValueError) with a message meant for the
user, so the GUI can show it in a message box and a macro gets a clear exception.
"""

import re

import Part

from mfgeom.errors import InputError  # noqa: F401  (raised here; refs.InputError for callers)

_FACE = re.compile(r"^Face[0-9]+$")
_VERTEX = re.compile(r"^Vertex[0-9]+$")

POINT_SOURCES = ("a Points object, a Mesh, a sketch or any Part object (its vertices), "
                 "or vertices of a shape")




def _label(obj):
    try:
        return f"'{obj.Label}'"
    except (AttributeError, RuntimeError):  # a deleted object raises RuntimeError
        return repr(obj)


def _check_object(obj, what):
    if obj is None:
        raise InputError(f"no {what} given")
    if not hasattr(obj, "TypeId") or not hasattr(obj, "Document"):
        raise InputError(f"the {what} must be a document object, got {type(obj).__name__}")
    try:
        doc = obj.Document
    except RuntimeError:
        doc = None
    if doc is None or doc.getObject(obj.Name) is None:
        raise InputError(f"the {what} object is not in a document (deleted?)")


def _subnames(subs):
    if subs is None:
        return []
    if isinstance(subs, str):
        return [subs] if subs else []
    return [s for s in subs if s]


def _sub_shape(obj, sub, shape_type, missing):
    """Sub-element ``sub`` of ``obj`` (global coordinates), which must be a
    ``shape_type``; InputError with ``missing`` otherwise."""
    try:
        shape = Part.getShape(obj, sub, needSubElement=True)
    except (Part.OCCError, ValueError, IndexError) as exc:
        raise InputError(f"{_label(obj)} has no {sub}: {exc}") from None
    if shape.isNull() or shape.ShapeType != shape_type:
        raise InputError(missing)
    return shape


def normalize_face_ref(face_ref):
    """``(obj, "FaceN")`` or ``(obj, ["FaceN"])`` -> ``(obj, "FaceN")``."""
    if not isinstance(face_ref, (tuple, list)) or len(face_ref) != 2:
        raise InputError('the face must be given as (object, "FaceN"), '
                         f"got {type(face_ref).__name__}")
    obj, subs = face_ref
    _check_object(obj, "face")
    subs = _subnames(subs)
    if len(subs) != 1:
        raise InputError(f"exactly one face of {_label(obj)} is needed, got {subs or 'none'}")
    sub = subs[0].split(".")[-1]  # "Body.Pad.Face3" from a selection -> "Face3"
    if not _FACE.match(sub):
        raise InputError(f"{sub} of {_label(obj)} is not a face (expected a name like Face1)")
    return obj, sub


def resolve_face(obj, sub):
    """The face ``sub`` of ``obj`` as a Part.Face in global coordinates."""
    _check_object(obj, "face")
    if not hasattr(obj, "Shape"):
        raise InputError(f"{_label(obj)} has no shape, so it has no faces")
    return _sub_shape(obj, sub, "Face",
                      f"{_label(obj)} has no {sub} (it has {len(obj.Shape.Faces)} faces)")


def normalize_points_ref(points_ref):
    """An object, ``(obj, [])`` or ``(obj, ["Vertex1", ...])`` -> ``(obj, [subs])``."""
    if isinstance(points_ref, (tuple, list)):
        if len(points_ref) != 2:
            raise InputError("points must be given as an object or (object, [\"Vertex1\", ...])")
        obj, subs = points_ref
    else:
        obj, subs = points_ref, []
    _check_object(obj, "points")
    subs = [s.split(".")[-1] for s in _subnames(subs)]
    if subs and _is_cloud(obj):
        subs = []  # picking a mesh or cloud in the view names a facet; the object is meant
    for s in subs:
        if not _VERTEX.match(s):
            raise InputError(f"{s} of {_label(obj)} is not a vertex; select vertices, "
                             f"or select the object itself in the tree ({POINT_SOURCES})")
    return obj, subs


def _is_cloud(obj):
    return obj.isDerivedFrom("Points::Feature") or obj.isDerivedFrom("Mesh::Feature")


def resolve_points(obj, subs):
    """The points of a point source as an (m, 3) float array in global coordinates."""
    _check_object(obj, "points")
    from mfgeom.app import pointcloud
    if obj.isDerivedFrom("Points::Feature"):
        # The kernel's matrix carries the object's placement
        pts = pointcloud.kernel_to_array(obj.Points)
    elif obj.isDerivedFrom("Mesh::Feature"):
        pts = pointcloud.mesh_points(obj.Mesh)
    elif _classified_points(obj) is not None:
        # the points of another classification (its Shape is empty)
        pts = pointcloud.kernel_to_array(_classified_points(obj))
    elif hasattr(obj, "Shape"):
        if subs:
            pts = pointcloud.vectors_to_array(
                _sub_shape(obj, s, "Vertex", f"{_label(obj)} has no {s}").Point for s in subs)
        else:
            pts = pointcloud.shape_points(Part.getShape(obj))
    else:
        raise InputError(f"{_label(obj)} ({obj.TypeId}) is not a point source; use "
                         + POINT_SOURCES)
    if not len(pts):
        raise InputError(f"{_label(obj)} has no points")
    return pts


def cloud_kernel(obj, subs):
    """The Points kernel (with the object's placement) that holds exactly the points
    resolve_points(obj, subs) gives, when the source is a cloud; else None.  Copying it
    costs a memcpy, building a new one from an array a conversion."""
    if subs:
        return None
    if obj.isDerivedFrom("Points::Feature"):
        return obj.Points
    return _classified_points(obj)


def _classified_points(obj):
    """The Points kernel property of a point classification feature, else None."""
    if "Points" in getattr(obj, "PropertiesList", ()) and \
            obj.getTypeIdOfProperty("Points") == "Points::PropertyPointKernel":
        return obj.Points
    return None


def check_points(obj, subs):
    """Raise InputError unless resolve_points(obj, subs) would give at least one point;
    cheaper than resolving for clouds, whose size is known without copying them."""
    _check_object(obj, "points")
    if obj.isDerivedFrom("Points::Feature"):
        count = obj.Points.CountPoints
    elif obj.isDerivedFrom("Mesh::Feature"):
        count = obj.Mesh.CountPoints
    elif _classified_points(obj) is not None:
        count = _classified_points(obj).CountPoints
    else:
        count = len(resolve_points(obj, subs))
    if count == 0:
        raise InputError(f"{_label(obj)} has no points")


def refs_from_selection(selection):
    """Split a selection into (face_ref, points_ref).

    ``selection`` is a list of ``(obj, [subnames])`` pairs (what
    ``Gui.Selection.getSelectionEx()`` gives as ``.Object``/``.SubElementNames``).
    One face and one point source (an object, or vertices of one object) are needed.
    """
    faces, vertex_sets, whole = [], [], []
    for obj, subs in selection:
        subs = [s.split(".")[-1] for s in _subnames(subs)]
        fsubs = [s for s in subs if _FACE.match(s)]
        vsubs = [s for s in subs if _VERTEX.match(s)]
        other = [s for s in subs if s not in fsubs and s not in vsubs]
        faces.extend((obj, s) for s in fsubs)
        if vsubs:
            vertex_sets.append((obj, vsubs))
        if other and _is_cloud(obj):
            whole.append(obj)  # a picked facet of a mesh stands for the mesh
        elif other:
            raise InputError(f"{', '.join(other)} of {_label(obj)} cannot be used: select "
                             f"one face and the points ({POINT_SOURCES})")
        elif not subs:
            whole.append(obj)
    if len(faces) != 1:
        raise InputError(f"select exactly one face (selected: {len(faces)}) and the points "
                         f"to classify ({POINT_SOURCES})")
    sources = vertex_sets + [(o, []) for o in whole]
    if not sources:
        raise InputError("select the points to classify as well: " + POINT_SOURCES)
    if len(sources) > 1:
        names = ", ".join(_label(o) for o, _s in sources)
        raise InputError(f"select points from one object only (got {names})")
    face_ref = normalize_face_ref(faces[0])
    points_ref = normalize_points_ref(sources[0])
    return face_ref, points_ref
