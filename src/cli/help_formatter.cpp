#include "brume/cli/help_formatter.h"

#include <sstream>
#include <vector>

namespace brume::cli {

namespace {

constexpr size_t kDescriptionColumn = 24;
constexpr size_t kLineWidth = 92;

// "-o, --output OUT"; flags have no value name.
std::string optionLabel(const CLI::Option& option) {
    std::string label;
    for (const std::string& s : option.get_snames()) label += (label.empty() ? "-" : ", -") + s;
    for (const std::string& l : option.get_lnames()) label += (label.empty() ? "--" : ", --") + l;
    if (option.get_type_size() != 0 && !option.get_type_name().empty()) label += " " + option.get_type_name();
    return label;
}

// Greedy word wrap; a word longer than `width` gets a line of its own.
std::vector<std::string> wrapWords(const std::string& text, size_t width) {
    std::vector<std::string> lines;
    std::istringstream words(text);
    std::string word, line;
    while (words >> word) {
        if (!line.empty() && line.size() + 1 + word.size() > width) {
            lines.push_back(line);
            line.clear();
        }
        line += (line.empty() ? "" : " ") + word;
    }
    if (!line.empty()) lines.push_back(line);
    return lines;
}

// The label, then the description from kDescriptionColumn on (on the next line when the
// label reaches into that column).
void appendOption(std::string& out, const CLI::Option& option) {
    std::string label = "  " + optionLabel(option);
    if (label.size() + 2 > kDescriptionColumn) {
        out += label + "\n";
        label.clear();
    }
    std::vector<std::string> lines = wrapWords(option.get_description(), kLineWidth - kDescriptionColumn);
    if (lines.empty()) lines.push_back("");
    for (const std::string& line : lines) {
        label.resize(kDescriptionColumn, ' ');
        out += label + line + "\n";
        label.clear();
    }
}

}  // namespace

std::string HelpFormatter::make_help(const CLI::App* app, std::string, CLI::AppFormatMode) const {
    std::string out = "usage: " + app->get_name() + " " + synopsis_ + "\n";
    if (!app->get_description().empty()) out += "\n" + app->get_description() + "\n";
    out += "\noptions:\n";
    const CLI::Option* help = app->get_help_ptr();
    auto listed = [help](const CLI::Option* o) {
        return o != help && o->nonpositional() && !o->get_group().empty() && !o->get_description().empty();
    };
    for (const CLI::Option* option : app->get_options(listed)) appendOption(out, *option);
    if (help) appendOption(out, *help);
    if (!app->get_footer().empty()) out += "\n" + app->get_footer() + "\n";
    return out;
}

}  // namespace brume::cli
