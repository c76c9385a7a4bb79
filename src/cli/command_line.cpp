#include "brume/cli/command_line.h"

#include <cstdio>
#include <memory>

#include "brume/cli/help_formatter.h"

namespace brume::cli {

namespace {

std::string firstLine(const std::string& text) { return text.substr(0, text.find('\n')); }

bool endsWith(const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// CLI11 2.1's wording of the two common mistakes, reworded as brume's scanner had them
// ("--spp needs a value", "--no-nee takes no value"); any other message keeps CLI11's first
// line, which names the option too.
std::string usageMessage(const CLI::ParseError& e) {
    std::string message = firstLine(e.what());
    size_t required = message.find(": 1 required ");
    if (required != std::string::npos && endsWith(message, " missing"))
        return message.substr(0, required) + " needs a value";
    const std::string flagValue = " was given a disallowed flag override";
    if (endsWith(message, flagValue)) {
        std::string name = message.substr(0, message.size() - flagValue.size());
        if (name.rfind('-', 0) != 0) name = (name.size() == 1 ? "-" : "--") + name;
        return name + " takes no value";
    }
    return message;
}

}  // namespace

void configureCommand(CLI::App& app, const std::string& synopsis) {
    app.formatter(std::make_shared<HelpFormatter>(synopsis));
    app.set_help_flag("-h,--help", "this text");
    app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast)->disable_flag_override();
    // Left over for parseCommand() to name in its own message.
    app.allow_extras();
}

void addSceneArgument(CLI::App& app, std::string& scene) {
    // More than one is refused by parseCommand(), after the unknown options (whose values
    // CLI11 takes for positional arguments).
    auto take = [&scene](const std::vector<std::string>& scenes) { scene = scenes.front(); };
    app.add_option_function<std::vector<std::string>>("scene", take, "the glTF scene file")->type_name("SCENE");
}

CLI::Option* addOption(CLI::App& app, const std::string& names, const std::string& valueName,
                       const std::string& description, std::function<void(const std::string&)> take) {
    return app.add_option_function<std::string>(names, std::move(take), description)->type_name(valueName);
}

bool parseCommand(CLI::App& app, const std::vector<std::string>& args) {
    std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them from the back
    try {
        app.parse(reversed);
    } catch (const CLI::CallForHelp&) {
        std::fputs(app.help().c_str(), stdout);
        return false;
    } catch (const CLI::ParseError& e) {
        throw UsageError(usageMessage(e));
    }
    // With allow_extras() CLI11 keeps unknown options (and the "--" it has honoured) aside.
    for (const std::string& extra : app.remaining()) {
        if (extra == "--") continue;
        if (extra.rfind('-', 0) == 0) throw UsageError("unknown option '" + extra.substr(0, extra.find('=')) + "'");
        throw UsageError("unexpected argument '" + extra + "'");
    }
    if (const CLI::Option* scene = app.get_option_no_throw("scene")) {
        const std::vector<std::string>& given = scene->results();
        if (given.size() > 1) throw UsageError("more than one scene given ('" + given[0] + "', '" + given[1] + "')");
    }
    return true;
}

}  // namespace brume::cli
