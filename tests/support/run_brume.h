// Runs the brume executable (BRUME_EXE) with stdout and stderr captured, in a directory of
// their own (so the output directories of the tests hold only what brume writes).
#pragma once
#include <sys/wait.h>

#include <cstdlib>
#include <string>

#include "support/scratch_files.h"

namespace brume::test {

struct BrumeResult {
    int code = -1;  // exit code; −1 if brume did not exit normally
    std::string out, err;
};

inline BrumeResult runBrume(const std::string& args) {
    TempDir capture;
    std::string command = quote(BRUME_EXE) + " " + args + " >" + quote(capture / "out") + " 2>" +
                          quote(capture / "err") + " </dev/null";
    int status = std::system(command.c_str());
    BrumeResult r;
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    r.out = readFile(capture / "out");
    r.err = readFile(capture / "err");
    return r;
}

}  // namespace brume::test
