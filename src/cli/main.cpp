// brume: dispatches to the sub-commands and turns their exceptions into one-line errors.
#include <cstdio>
#include <exception>
#include <new>
#include <string>
#include <vector>

#include "brume/cli/commands.h"
#include "brume/scene/gltf_loader.h"

namespace {

const char* const kUsage =
    "usage: brume COMMAND [arguments]\n"
    "\n"
    "commands:\n"
    "  render SCENE -o OUT [options]   render a glTF scene to .exr, .pfm or .png\n"
    "  raybench SCENE [options]        path tracer rays/s against raw Embree; thread scaling\n"
    "  bench SCENE --out DIR [options] equal-time error and efficiency of light-transport methods\n"
    "\n"
    "'brume COMMAND --help' describes a command's options.\n"
    "exit codes: 0 success, 1 scene/image/run-time error, 2 bad command line,\n"
    "130 stopped by SIGINT (Ctrl-C), 143 stopped by SIGTERM.\n";

// Errors are one line: the first line of the message.
void reportError(const std::string& message) {
    std::string line = message.substr(0, message.find('\n'));
    std::fprintf(stderr, "brume: error: %s\n", line.c_str());
}

}  // namespace

int main(int argc, char** argv) {
    using namespace brume::cli;
    if (argc < 2) {
        std::fputs(kUsage, stderr);
        return kExitUsage;
    }
    std::string command = argv[1];
    std::vector<std::string> args(argv + 2, argv + argc);
    try {
        if (command == "-h" || command == "--help" || command == "help") {
            std::fputs(kUsage, stdout);
            return kExitOk;
        }
        if (command == "render") return runRender(args);
        if (command == "raybench") return runRaybench(args);
        if (command == "bench") return runBench(args);
        throw UsageError("unknown command '" + command + "' (commands: render, raybench, bench; see brume --help)");
    } catch (const UsageError& e) {
        reportError(e.what());
        return kExitUsage;
    } catch (const brume::SceneError& e) {
        reportError(e.what());
        return kExitFailure;
    } catch (const std::bad_alloc&) {
        reportError("out of memory");
        return kExitFailure;
    } catch (const std::exception& e) {
        reportError(e.what());
        return kExitFailure;
    }
}
