// How the brume executable ends: its exit codes, and the exception for a bad command line.
#pragma once
#include <stdexcept>

namespace brume::cli {

// A bad command line: main() prints its one-line message and exits with kExitUsage.
struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;  // scene, image or other run-time errors
constexpr int kExitUsage = 2;    // bad command line
constexpr int kExitInterrupted = 130;

}  // namespace brume::cli
