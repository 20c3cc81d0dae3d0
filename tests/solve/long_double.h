/* long_double.h: generated/'s kernels in extended precision, for
 * hybrid_reference alone (tests/CMakeLists.txt forces it in front of each
 * generated file it compiles).  Every double becomes a long double, and
 * <tgmath.h> makes sin, cos, atan, sqrt choose their long double functions. */
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <tgmath.h>
#define double long double
