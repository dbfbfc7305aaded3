#pragma once

namespace pr {

// Parses the command line, dispatches to a subcommand and maps errors to exit codes
// (0 ok, 1 bad input or runtime failure with one line on stderr, 2 bad usage).
int run_cli(int argc, char** argv);

} // namespace pr
