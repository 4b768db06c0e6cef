# SPDX-License-Identifier: LGPL-2.1-or-later
"""The FreeCAD App layer of mfgeom: feature proxies, reference resolution and the geometry
that needs FreeCAD's Part module.  Works in freecadcmd; nothing here imports FreeCADGui.

One module per feature, plus the shared helpers (feature_base: what every proxy shares;
refs: document references -> geometry; pointcloud: points in and out of FreeCAD's
containers; preferences):

* point classification of points against a trimmed face (pointclass, face_domain);
* parting analysis: mould parting direction with core / cavity / undercut faces, NC
  3-axis set-ups, draft check (parting_feature, parting_batch, gauss_map) and the ray
  (line-of-sight) check of the pull direction (ray_check);
* rotational sweep of a solid or mesh about an axis (sweep_feature) and the clearance
  check of the swept volume against other parts (clearance);
* medial surface of a solid coloured by wall thickness (medial_surface_feature), the
  mid-surface for FEM with the local thickness (mid_surface_feature) and the medial axis
  of a planar face (medial_axis_feature)."""
