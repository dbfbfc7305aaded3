#include "app/cli.hpp"

#include "app/commands.hpp"
#include "core/error.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace pr {

namespace {

// An option's name, a hidden one's too (CLI11's get_name() is empty for an option out of the help's
// groups: view's --backend, whose usage errors read ": given 2 times"; found by an exploratory
// session, fifty-third).
std::string option_name(const CLI::Option& option)
{
    if (std::string name = option.get_name(); !name.empty()) return name;
    if (!option.get_lnames().empty()) return "--" + option.get_lnames().front();
    if (!option.get_snames().empty()) return "-" + option.get_snames().front();
    return {};
}

// CLI11's own texts for two usage errors say what it checked, not what the user did wrong:
// "At Most 1 required but received 2" for an option given twice, "A subcommand is required" for
// `prismrelief foo`. Anything else keeps CLI11's message.
std::string usage_message(CLI::App& app, const CLI::ParseError& e, int argc, char** argv)
{
    const std::vector<CLI::App*> commands = app.get_subcommands({});
    bool any_parsed = false;
    for (CLI::App* command : commands) {
        if (!command->parsed()) continue;
        any_parsed = true;
        if (dynamic_cast<const CLI::ArgumentMismatch*>(&e))
            for (const CLI::Option* option : command->get_options())
                if (option->get_items_expected_max() == 1 && option->count() > 1)
                    return option_name(*option) + ": given " + std::to_string(option->count()) +
                           " times; give it once";
        // A value that is not a number: "Could not convert: --frames = 1e3" said what failed
        // inside, not what the option takes (found by an exploratory session).
        if (dynamic_cast<const CLI::ConversionError*>(&e)) {
            const std::string what = e.what(), prefix = "Could not convert: ";
            const std::size_t eq = what.find(" = ");
            if (what.rfind(prefix, 0) == 0 && eq != std::string::npos) {
                const std::string name = what.substr(prefix.size(), eq - prefix.size());
                const CLI::Option* option = command->get_option_no_throw(name);
                const std::string type = option ? option->get_type_name() : "";
                const bool whole = type.find("INT") != std::string::npos;
                return name + ": expected " + (whole ? "a whole number" : "a number") + ", got '" +
                       what.substr(eq + 3) + "'";
            }
        }
        // Arguments the command does not take, named in the order given (CLI11's message listed
        // them backwards: "not expected: 4 --msaa" for `compare --msaa 4`), an option first. Before
        // a missing required option: CLI11 checks those first, so a misspelt `--outt x.png` was
        // "--out is required", and `render --bogus` too (found by an audit).
        if (dynamic_cast<const CLI::ExtrasError*>(&e) ||
            (dynamic_cast<const CLI::RequiredError*>(&e) && !command->remaining().empty())) {
            const std::vector<std::string> extra = command->remaining();
            // (An option, not a negative number: `--depth 0.1 -3` has an extra value.)
            const auto option = std::find_if(extra.begin(), extra.end(), [](const std::string& a) {
                return a.size() > 1 && a[0] == '-' && !std::isdigit(static_cast<unsigned char>(a[1])) && a[1] != '.';
            });
            if (option != extra.end())
                return "'" + option->substr(0, option->find('=')) + "': " + command->get_name() + " has no such option";
            if (!extra.empty()) return "'" + extra.front() + "': " + command->get_name() + " takes no such argument";
        }
    }
    // CLI11's own message about a hidden option starts with its empty name (": 1 required TEXT
    // missing"): the hidden option the words name.
    if (const std::string what = e.what(); what.rfind(": ", 0) == 0)
        for (CLI::App* command : commands)
            if (command->parsed())
                for (const CLI::Option* option : command->get_options())
                    if (option->get_group().empty())
                        for (int i = 1; i < argc; ++i)
                            if (const std::string name = option_name(*option); !name.empty() && argv[i] == name)
                                return name + what;
    if (!any_parsed && argc > 1 && argv[1][0] != '-') {
        std::string names;
        for (std::size_t i = 0; i < commands.size(); ++i)
            names += (i == 0 ? "" : i + 1 == commands.size() ? " or " : ", ") + commands[i]->get_name();
        return "unknown subcommand '" + std::string(argv[1]) + "' (expected " + names + ")";
    }
    return e.what();
}

// Where a usage message sends the user: the subcommand's own help where the words name one
// (`render --out o.png` said "see prismrelief render --help" but `render --mesh m.obj`
// "see prismrelief --help", which lists no render option; found by an exploratory session,
// fiftieth), else the program's.
std::string help_hint(const CLI::App& app, int argc, char** argv)
{
    if (argc > 1)
        for (const CLI::App* command : app.get_subcommands({}))
            if (command->get_name() == argv[1]) return "see prismrelief " + command->get_name() + " --help";
    return "see prismrelief --help";
}

// What a command printed must have reached its destination: a table sent to a full disk
// (`> /dev/full`) was lost with exit 0.
// `earlier`: the errno of writes already made (CLI11 prints the help through std::cout, which
// fails as it writes: the flush finds nothing left to write).
int check_stdout(int earlier = 0)
{
    errno = 0;
    if (std::fflush(stdout) == 0 && !std::ferror(stdout)) return kExitOk;
    const int err = errno != 0 ? errno : earlier;
    std::fprintf(stderr, "prismrelief: error: standard output: cannot write%s%s\n", err ? ": " : "",
                 err ? std::strerror(err) : "");
    return kExitFailure;
}

// --help and --version end the parse where they stand (as getopt's callers do): what follows is
// not read. What came before is: an unknown subcommand or option there is usage, as without them
// (`prismrelief frobnicate --version` printed the version and exited 0; found by an audit).
int help_or_usage(CLI::App& app, const CLI::ParseError& e, int argc, char** argv)
{
    std::vector<std::string> extra = app.remaining();
    for (const CLI::App* command : app.get_subcommands({}))
        if (command->parsed() && extra.empty()) extra = command->remaining();
    // (The help and the version must reach stdout as a command's output must: lost on a full or
    // closed stdout with exit 0 until the fiftieth session; found by an exploratory session.)
    if (extra.empty()) {
        errno = 0;
        const int status = app.exit(e);
        return status == kExitOk ? check_stdout(errno) : status;
    }
    const CLI::ExtrasError unknown(extra);
    std::fprintf(stderr, "prismrelief: usage: %s (%s)\n", one_line(usage_message(app, unknown, argc, argv)).c_str(),
                 help_hint(app, argc, argv).c_str());
    return kExitUsage;
}

// The options that name a file or folder.
constexpr const char* kFileOptions[] = {"--out",        "--json", "--scene", "--mesh",  "--height",    "--color",
                                        "--cache-dir", "--shader-dir", "--drop", "--tiles", "--screenshot"};

// A file option given an empty value (`--json ""`, a script's unset variable): CLI11 takes it as
// not given, so the command "succeeded" without its report (compare, bench, conemap --json,
// compare --out), drew without its scene or colour map, or used the default cache folder.
void refuse_empty_file_names(const CLI::App& command)
{
    for (const char* name : kFileOptions) {
        const CLI::Option* option = command.get_option_no_throw(name);
        if (option == nullptr || option->count() == 0) continue;
        for (const std::string& value : option->results())
            if (value.empty()) throw Error(name, "empty file name");
    }
}

// A command that draws a scene and was given neither --mesh nor --scene: usage (exit 2), as a
// missing --out is (it was exit 1, "--mesh: required", as if an input had been bad).
bool scene_missing(const CLI::App& command)
{
    const CLI::Option* mesh = command.get_option_no_throw("--mesh");
    const CLI::Option* scene = command.get_option_no_throw("--scene");
    if (mesh == nullptr || scene == nullptr || mesh->count() > 0 || scene->count() > 0) return false;
    std::fprintf(stderr,
                 "prismrelief: usage: --mesh FILE or --scene FILE.json is required (see prismrelief %s --help)\n",
                 command.get_name().c_str());
    return true;
}


// Whether a command-line word is an option's name (`--name`, `--name=value`, `-h`), never a value:
// negative numbers (`-0.5`, `-1,2,3`) and a lone "-" are values.
bool looks_like_option(const std::string& word)
{
    return word == "-h" || (word.size() > 2 && word.starts_with("--") && std::isalpha(static_cast<unsigned char>(word[2])));
}

// Whether a command-line word ends the parse where it stands: --help, -h, --version.
bool ends_parse(const std::string& word) { return word == "--help" || word == "-h" || word == "--version"; }

} // namespace

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

    // "--depth=" (an empty value after "="): CLI11 took the next argument as the value ("--depth=
    // --size 64x48": "Could not convert: --depth = --size"). Given as the flag and an empty value,
    // the flag's own check says what is wrong ("expected a number, got an empty value").
    // Only for an option that takes a value (a flag given "=" is CLI11's to refuse), and not past
    // a "--".
    // How many values the option `name` takes (the first command that has it): 0 for a flag,
    // -1 where no command has such an option.
    const auto values_taken = [&app](const std::string& name) {
        for (const CLI::App* command : app.get_subcommands({}))
            if (const CLI::Option* option = command->get_option_no_throw(name)) return option->get_items_expected_max();
        return -1;
    };
    const auto takes_value = [&](const std::string& name) { return values_taken(name) > 0; };
    const auto is_flag = [&](const std::string& name) { return values_taken(name) == 0; };
    std::vector<std::string> args(argv, argv + argc);
    // An option before the subcommand: "--bogus" alone said "A subcommand is required", and
    // "--size 64x64 render …" CLI11's "The following arguments were not expected: 64x64 --size"
    // (found by an exploratory session, forty-ninth). Only --help and --version go there.
    if (args.size() > 1 && args[1].size() > 1 && args[1][0] == '-' && !ends_parse(args[1].substr(0, args[1].find('=')))) {
        const std::string name = args[1].substr(0, args[1].find('='));
        std::fprintf(stderr,
                     "prismrelief: usage: '%s': options go after the subcommand (prismrelief render|compare|bench|conemap|view "
                     "[OPTIONS]; see prismrelief --help)\n",
                     one_line(name).c_str());
        return kExitUsage;
    }
    std::vector<std::string> split;
    bool options_end = false, help_asked = false;
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        options_end = options_end || a == "--";
        // --help and --version end the parse where they stand (as getopt's callers do): nothing
        // after them is read, and a flag just before them that takes a value is left out (CLI11
        // took the word for its value: `--json --help` rendered and wrote the report to a file
        // named "--help"; found by a review, thirty-sixth).
        if (i > 0 && !options_end && ends_parse(a)) {
            help_asked = a != "--version";
            if (!split.empty() && split.back().starts_with("--") && split.back().find('=') == std::string::npos &&
                takes_value(split.back()))
                split.pop_back();
            split.push_back(a);
            break;
        }
        // A flag given a value ("--no-cache=false"): CLI11 read true and false words, numbers
        // (-1 false) and "" (true) there, and said "expected a number" of any other word, so
        // `--no-cache=false` used the cache without a word (found by an exploratory session,
        // forty-ninth). A flag is on where given and off where not: a value is usage.
        if (const std::size_t eq = a.find('=');
            i > 0 && !options_end && a.starts_with("--") && eq != std::string::npos && is_flag(a.substr(0, eq))) {
            std::fprintf(stderr, "prismrelief: usage: %s takes no value, got '%s' (give the flag alone to turn it on; %s)\n",
                         one_line(a.substr(0, eq)).c_str(), one_line(a.substr(eq + 1)).c_str(), help_hint(app, argc, argv).c_str());
            return kExitUsage;
        }
        // An option that takes a value, followed by another option: CLI11 took the option for
        // the value (`--json --depth-write` wrote the report to a file named "--depth-write"
        // without depth writes, exit 0; `--techniques --size 16x16` blamed "16x16"; found by an
        // exploratory session, thirty-sixth). A file whose name starts with "--" is given as
        // ./--name. (Before --help or --version, above: the flag is left out.)
        const bool ends_next = i + 1 < args.size() && ends_parse(args[i + 1]);
        if (i > 0 && !options_end && !ends_next && a.starts_with("--") && a.find('=') == std::string::npos &&
            takes_value(a) && i + 1 < args.size() && looks_like_option(args[i + 1])) {
            const bool file = std::find(std::begin(kFileOptions), std::end(kFileOptions), a) != std::end(kFileOptions);
            std::fprintf(stderr, "prismrelief: usage: %s: expected a value, got the option '%s'%s (%s)\n",
                         one_line(a).c_str(), one_line(args[i + 1].substr(0, args[i + 1].find('='))).c_str(),
                         file ? one_line(" (a file of that name: ./" + args[i + 1] + ")").c_str() : "",
                         help_hint(app, argc, argv).c_str());
            return kExitUsage;
        }
        const std::string name = a.size() > 3 && a.back() == '=' ? a.substr(0, a.size() - 1) : std::string();
        if (i > 0 && !options_end && name.starts_with("--") && name.find('=') == std::string::npos &&
            takes_value(name)) {
            split.push_back(name);
            split.emplace_back();
        } else {
            split.push_back(a);
        }
    }
    std::vector<char*> split_argv;
    for (std::string& a : split) split_argv.push_back(a.data());
    split_argv.push_back(nullptr);
    argc = int(split.size());
    argv = split_argv.data();

    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return help_or_usage(app, e, argc, argv);
    } catch (const CLI::CallForAllHelp& e) {
        return help_or_usage(app, e, argc, argv);
    } catch (const CLI::CallForVersion& e) {
        return help_or_usage(app, e, argc, argv);
    } catch (const CLI::ParseError& e) {
        // --help next to a bad value (`render --steps abc --help`): the help, as CLI11 gives it
        // where the values are good (it converts them before it looks for --help; found by an
        // exploratory session, thirty-sixth). An unknown option or argument stays usage.
        if (help_asked && (dynamic_cast<const CLI::ConversionError*>(&e) || dynamic_cast<const CLI::ValidationError*>(&e) ||
                           dynamic_cast<const CLI::ArgumentMismatch*>(&e)))
            return help_or_usage(app, CLI::CallForHelp(), argc, argv); // (an unknown option stays usage)
        std::fprintf(stderr, "prismrelief: usage: %s (%s)\n", one_line(usage_message(app, e, argc, argv)).c_str(),
                     help_hint(app, argc, argv).c_str());
        return kExitUsage;
    }

    std::string running = "prismrelief"; // the subcommand run, for a message that has no subject
    try {
        // Subcommands were registered in the order of `actions`; run the one that was parsed.
        const std::vector<CLI::App*> all = app.get_subcommands({});
        for (std::size_t i = 0; i < all.size(); ++i) {
            if (!all[i]->parsed()) continue;
            running = all[i]->get_name();
            if (scene_missing(*all[i])) return kExitUsage;
            refuse_empty_file_names(*all[i]);
            hold_warnings(); // until the command has accepted its inputs (release_warnings)
            const int status = actions[i]();
            release_warnings();
            return status == kExitOk ? check_stdout() : status;
        }
        return kExitUsage;
    } catch (const Error& e) {
        drop_warnings(); // (those of inputs read before bad input was found: it is one line alone)
        // One line, whatever the names it quotes hold; a compiler's log after it.
        std::fprintf(stderr, "prismrelief: error: %s\n", one_line(e.subject() + ": " + e.problem()).c_str());
        if (!e.detail().empty()) std::fprintf(stderr, "%s\n", e.detail().c_str());
    } catch (const std::bad_alloc&) {
        drop_warnings();
        // Where no step named its input (a map, a mesh, the reference: those do), the command.
        std::fprintf(stderr, "prismrelief: error: %s: out of memory\n", running.c_str());
    } catch (const std::exception& e) {
        drop_warnings();
        std::fprintf(stderr, "prismrelief: error: %s\n", one_line(e.what()).c_str());
    }
    return kExitFailure;
}

} // namespace pr
