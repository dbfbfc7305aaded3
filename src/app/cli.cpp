#include "app/cli.hpp"

#include "app/commands.hpp"
#include "core/error.hpp"

#include <cstdio>
#include <exception>
#include <new>

namespace pr {

int run_cli(int argc, char** argv)
{
    CLI::App app{"prismrelief: height-field displacement with true silhouettes.\n"
                 "Renders meshes headless (OpenGL 4.5 core on OSMesa/llvmpipe, or EGL) with prism\n"
                 "shells (--technique prism) or the parallax family, measures them against true\n"
                 "tessellated displacement (compare) and times them (bench). Exit codes: 0 ok,\n"
                 "1 bad input or runtime failure (one line on stderr), 2 bad usage.",
                 "prismrelief"};
    app.set_version_flag("--version", std::string("prismrelief ") + PRISMRELIEF_VERSION);
    app.require_subcommand(1);
    app.fallthrough(false);
    app.get_formatter()->column_width(34);

    std::vector<CommandAction> actions;
    actions.push_back(add_render_command(app));
    actions.push_back(add_compare_command(app));
    actions.push_back(add_bench_command(app));
    actions.push_back(add_conemap_command(app));
    actions.push_back(add_view_command(app));

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForAllHelp& e) {
        return app.exit(e);
    } catch (const CLI::CallForVersion& e) {
        return app.exit(e);
    } catch (const CLI::ParseError& e) {
        std::fprintf(stderr, "prismrelief: usage: %s (see prismrelief --help)\n", e.what());
        return kExitUsage;
    }

    try {
        // Subcommands were registered in the order of `actions`; run the one that was parsed.
        const std::vector<CLI::App*> all = app.get_subcommands({});
        for (std::size_t i = 0; i < all.size(); ++i)
            if (all[i]->parsed()) return actions[i]();
        return kExitUsage;
    } catch (const Error& e) {
        std::fprintf(stderr, "prismrelief: error: %s\n", e.what());
    } catch (const std::bad_alloc&) {
        std::fprintf(stderr, "prismrelief: error: out of memory\n");
    } catch (const std::exception& e) {
        std::fprintf(stderr, "prismrelief: error: %s\n", e.what());
    }
    return kExitFailure;
}

} // namespace pr
