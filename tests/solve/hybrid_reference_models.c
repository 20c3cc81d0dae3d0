/* hybrid_reference_models.c: the two models hybrid_reference links but never
 * calls.  The descriptors of the twist_integrated models (which the
 * unilateral models' kernels call) point to their twins in tilt-vector
 * coordinates (usm_model.other_coordinates); hybrid_reference never follows
 * that pointer, so empty descriptors stand in for those models instead of
 * compiling the two largest generated files a second time, in long double.
 * A kernel of theirs that it did call would fail the link, not the run. */
#include "usm_kernels.h"

const usm_model usm_model_3dof_tilt = {0};
const usm_model usm_model_4dof_tilt = {0};
