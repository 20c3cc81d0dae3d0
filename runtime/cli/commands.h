/* commands.h: the usm subcommands.
 *
 * Each subcommand lives in its own <name>_cmd.c and has one entry point
 *     int cli_<name>_main(int argc, char **argv);
 * called with argv[0] = the subcommand's name.  It returns the exit status
 * (USM_OK, USM_EFAILED, USM_EINPUT, USM_ENOSOLUTION) and prints its usage on
 * stdout for "--help".  To add one, declare it here and add a line to the
 * table in main.c.
 */
#ifndef USM_CLI_COMMANDS_H
#define USM_CLI_COMMANDS_H

int cli_steady_main(int argc, char **argv);
int cli_sweep_main(int argc, char **argv);
int cli_variants_main(int argc, char **argv);
int cli_equations_main(int argc, char **argv);
int cli_report_main(int argc, char **argv);
int cli_map_main(int argc, char **argv);
int cli_simulate_main(int argc, char **argv);
int cli_sensitivity_main(int argc, char **argv);
int cli_optimize_main(int argc, char **argv);
int cli_tolerance_main(int argc, char **argv);
int cli_periodic_main(int argc, char **argv);
int cli_pareto_main(int argc, char **argv);

#endif /* USM_CLI_COMMANDS_H */
