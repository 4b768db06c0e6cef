/* SPDX-License-Identifier: LGPL-2.1-or-later */
/* rotsweep.c - the rotational swept volume of a closed polyhedron (seed 003). */
#include <stdlib.h>
#include <string.h>

#include "mesh.h"
#include "mfg_internal.h"

#define MFG_TWO_PI 6.283185307179586476925286766559

/* Arguments other than the mesh (which mfg_mesh_require_closed checks). */
static mfg_status check_sweep_args(const double *axis_point, const double *axis_dir,
                                   double angle, double tolerance, mfg_mesh **out_mesh)
{
    if (!axis_point || !axis_dir || !out_mesh)
        return mfg_fail(MFG_ERR_NULL, "rotational sweep: %s is NULL",
                        !axis_point ? "axis_point" : !axis_dir ? "axis_direction" : "out_mesh");
    for (int k = 0; k < 3; k++) {
        if (!mfg_coord_ok(axis_point[k]))
            return mfg_fail(MFG_ERR_INVALID, "rotational sweep: axis point coordinate %d is %g "
                            "(not finite or out of range)", k, axis_point[k]);
        if (!mfg_coord_ok(axis_dir[k]))
            return mfg_fail(MFG_ERR_INVALID, "rotational sweep: axis direction component %d is "
                            "%g (not finite or out of range)", k, axis_dir[k]);
    }
    if (axis_dir[0] == 0 && axis_dir[1] == 0 && axis_dir[2] == 0)
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: the axis direction is the zero vector");
    if (!(angle > 0) || !(angle <= MFG_TWO_PI + 1e-12))
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: angle %g rad is outside (0, 2*pi]",
                        angle);
    if (!(tolerance > 0) || !mfg_coord_ok(tolerance))
        return mfg_fail(MFG_ERR_INVALID, "rotational sweep: tolerance %g must be positive and "
                        "finite", tolerance);
    return MFG_OK;
}

mfg_status mfg_rotational_sweep(const double *xyz, int64_t nvertices, const int64_t *triangles,
                                int64_t ntriangles, const double axis_point[3],
                                const double axis_direction[3], double angle, double tolerance,
                                mfg_mesh **out_mesh, mfg_sweep_stats *out_stats)
{
    mfg_status st = check_sweep_args(axis_point, axis_direction, angle, tolerance, out_mesh);
    if (st != MFG_OK)
        return st;
    int64_t *nb = NULL;
    st = mfg_mesh_require_closed(xyz, nvertices, triangles, ntriangles, NULL, &nb);
    if (st != MFG_OK)
        return st;
    free(nb);
    (void)out_stats;
    return mfg_fail(MFG_ERR_INTERNAL, "rotational sweep: not implemented yet");
}
