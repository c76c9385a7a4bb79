// Command-line parsing for the brume commands: a scanner over argv that understands
// "--flag value", "--flag=value", "-o value" and "--" (end of options), and checked number
// parsers. Every problem is a UsageError with a one-line message (exit code 2).
#pragma once
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace brume::cli {

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Exit codes of the brume executable.
constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;  // scene, image or other run-time errors
constexpr int kExitUsage = 2;    // bad command line
constexpr int kExitInterrupted = 130;

class ArgScanner {
public:
    explicit ArgScanner(std::vector<std::string> args) : args_(std::move(args)) {}

    // Moves to the next argument; false when there are none left.
    bool next();
    // The current argument: an option's name ("--spp", "-o") or a positional argument.
    const std::string& current() const { return name_; }
    bool isOption() const { return option_; }
    // The value of the current option: the part after '=' or the next argument.
    std::string value();
    // For options without a value: rejects "--flag=value".
    void noValue() const;
    // UsageError for the current option when it is not one the command knows.
    [[noreturn]] void unknown() const;

private:
    std::vector<std::string> args_;
    size_t index_ = 0;
    std::string name_;
    std::string inlineValue_;
    bool hasInlineValue_ = false;
    bool option_ = false;
    bool optionsEnded_ = false;
};

struct Resolution {
    int width = 0, height = 0;
};

constexpr int kMaxImageSide = 16384;
constexpr int64_t kMaxImagePixels = int64_t(1) << 27;

// Whole decimal numbers in [lo, hi]; `what` names the option in messages.
int64_t parseInteger(const std::string& what, const std::string& text, int64_t lo, int64_t hi);
uint64_t parseUnsigned64(const std::string& what, const std::string& text);
// A finite decimal number in (0, hi].
double parsePositiveSeconds(const std::string& what, const std::string& text, double hi);
// "WxH", each side in [1, kMaxImageSide], at most kMaxImagePixels pixels.
Resolution parseResolution(const std::string& what, const std::string& text);
// Throws UsageError unless the resolution is within the limits above.
void checkResolution(const std::string& what, Resolution r);

}  // namespace brume::cli
