// prismrelief view: placeholder until its issue lands (replaced by the real command).
#include "app/commands.hpp"
#include "core/error.hpp"

namespace pr {

CommandAction add_view_command(CLI::App& app)
{
    app.add_subcommand("view", "(not built yet)");
    return []() -> int { throw Error("view", "not built yet"); };
}

} // namespace pr
