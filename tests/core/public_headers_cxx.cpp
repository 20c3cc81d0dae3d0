// The public headers as C++: every one of them (usm_public_headers.h, written
// by tests/CMakeLists.txt, includes runtime/usm*.h and the generated headers),
// together in one translation unit, and a few calls through them.
#include "usm_public_headers.h"

#include <cstdio>
#include <cstring>

int main()
{
    usm_params p;
    usm_params_default(&p);
    const usm_model *m = usm_model_find("3dof");
    if (!m || m->nx > USM_MAX_NX) {
        std::fprintf(stderr, "cxx_headers: no 3dof model\n");
        return 1;
    }
    // A kernel through its restrict-qualified pointers (restrict -> __restrict).
    double x[USM_MAX_NX] = {0.0};
    double mass[USM_MAX_NX * USM_MAX_NX];
    x[1] = 1e-4;  // theta > 0: away from the z-x-z singularity
    m->mass(x, &p, mass);
    if (!(mass[0] == mass[0])) {
        std::fprintf(stderr, "cxx_headers: mass matrix is NaN\n");
        return 1;
    }
    char msg[USM_MSG_LEN];
    if (usm_params_set(&p, "no_such_parameter", 1.0, msg) != USM_EINPUT) {
        std::fprintf(stderr, "cxx_headers: usm_params_set accepted an unknown name\n");
        return 1;
    }
    std::printf("usm %s, generator %s (headers %s); %s\n", usm_version(), usm_generator_version(),
                USM_GENERATOR_VERSION, msg);
    return std::strcmp(usm_generator_version(), USM_GENERATOR_VERSION) == 0 ? 0 : 1;
}
