/* report_paper_values.c: THE PAPER'S PUBLISHED VALUES, typed in.
 *
 * This is the only place in `usm report` where numbers are typed in: each
 * entry is a value printed in the paper ("Modeling and stability analysis
 * for an ultrasonic motor"), exactly as printed, with where it is printed.
 * Everything the report sets beside them is computed at run time through
 * the library.  Misprints are kept as printed; the report explains them
 * (see also tests/paper_check.py, which holds the same values).
 */
#include "report.h"

const report_paper report_paper_values = {
    /* ---- section 3, stationary solution of the 3-DOF (stick) model ---- */
    .theta3 = {"Sec. 3", "tilt theta (3-DOF)", "0.81836e-4", 0.81836e-4, "rad"},
    .alpha3 = {"Sec. 3", "phase alpha (3-DOF)", "5.16 degrees", 5.16, "\"degrees\""},
    .beta3 = {"Sec. 3, (3.6)", "phase beta (3-DOF)", "-1.98 degrees", -1.98, "\"degrees\""},

    /* ---- section 5, stationary solution of the 4-DOF (slip) model ---- */
    .speed4 = {"Sec. 5", "rotor speed phidot_R (4-DOF)", "-10.34 1/s", -10.34, "1/s"},
    .theta4 = {"Sec. 5", "tilt theta (4-DOF)", "0.81836e-4", 0.81836e-4, "rad"},
    .alpha4 = {"Sec. 5", "phase alpha (4-DOF)", "5.12", 5.12, "(rad)"},
    .beta4 = {"Sec. 5", "phase beta (4-DOF)", "-5.12", -5.12, "(rad)"},

    /* ---- Table 3: eigenvalues of B, 3-DOF model ---- */
    .table3 = {
        {"lambda_1,2", "-0.7101 ± 0.5908i", -0.7101, 0.5908, "0.9238", 0.9238},
        {"lambda_3", "0.8416", 0.8416, 0.0, "0.8416", 0.8416},
        {"lambda_4", "0.8272", 0.8272, 0.0, "0.8272", 0.8272},
        {"lambda_5,6", "-0.6570 ± 0.0189i", -0.6570, 0.0189, "0.6573", 0.6573},
    },
    .n3 = 4,

    /* ---- Table 4: eigenvalues of B, 4-DOF model ---- */
    .table4 = {
        {"lambda_1,2", "0.2616 ± 0.4934i", 0.2616, 0.4934, "0.5585", 0.5585},
        {"lambda_3", "0.7702", 0.7702, 0.0, "0.7702", 0.7702},
        {"lambda_4", "0.8269", 0.8269, 0.0, "0.8269", 0.8269},
        {"lambda_5,6", "-0.8021 ± 0.2712i", -0.8021, 0.2712, "0.8467", 0.8467},
        {"lambda_7", "0.8654", 0.8654, 0.0, "0.8654", 0.8654},
        {"lambda_8", "1", 1.0, 0.0, "1", 1.0},
    },
    .n4 = 6,

    /* ---- motor characteristics, text of section 3 (Figs. 9 and 10) ---- */
    .f_max = {"Sec. 3, Fig. 9", "speed maximum \"near an eigenfrequency of the stator\"",
              "36.8 kHz", 36.8e3, "Hz"},
    .slip_load = {"Sec. 3, Fig. 10", "\"Above a load of 9.7 Nmm slip will occur\"", "9.7 Nmm",
                  9.7e-3, "N m"},

    /* ---- conclusion ---- */
    .speed_ratio = {"Sec. 6", "speed reduction Omega / rotor speed", "≈ 10^4", 1e4, "1"},
};
