// prismrelief conemap: placeholder until its issue lands (replaced by the real command).
#include "app/commands.hpp"
#include "core/error.hpp"

namespace pr {

CommandAction add_conemap_command(CLI::App& app)
{
    app.add_subcommand("conemap", "(not built yet)");
    return []() -> int { throw Error("conemap", "not built yet"); };
}

} // namespace pr
