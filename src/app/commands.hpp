#pragma once
// One function per subcommand: each registers its options on the parser and returns the action
// to run after parsing.
#include <CLI/CLI.hpp>

#include <functional>

namespace pr {

using CommandAction = std::function<int()>;

CommandAction add_render_command(CLI::App& app);
CommandAction add_compare_command(CLI::App& app);
CommandAction add_bench_command(CLI::App& app);
CommandAction add_conemap_command(CLI::App& app); // conemap_cmd.cpp
CommandAction add_view_command(CLI::App& app);    // view_cmd.cpp

} // namespace pr
