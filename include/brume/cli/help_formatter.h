// The help of a brume command, in the layout of `brume --help`:
//
//   usage: brume render SCENE -o OUT [options]
//
//   <the App's description>
//
//   options:
//     -o, --output OUT      <the option's description, word-wrapped>
//     ...
//     -h, --help            this text
//
//   <the App's footer>
//
// Options without a description (testing aids) and positional arguments (named in the
// synopsis) are left out.
#pragma once
#include <CLI/CLI.hpp>

#include <string>

namespace brume::cli {

class HelpFormatter : public CLI::Formatter {
public:
    explicit HelpFormatter(std::string synopsis) : synopsis_(std::move(synopsis)) {}
    std::string make_help(const CLI::App* app, std::string name, CLI::AppFormatMode mode) const override;

private:
    std::string synopsis_;
};

}  // namespace brume::cli
