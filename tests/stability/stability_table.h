// The stability table, printed row by row on stdout as the cases run (markdown, for
// docs/results.md): one row per case and method, numbers as in stability_compare.h.
#pragma once
#include <cstdio>
#include <string>

#include "stability/stability_compare.h"

namespace brume::test {

inline void printHeader() {
    static bool done = false;
    if (done) return;
    done = true;
    std::printf("| case | method | spp | max abs z | z mean | bias | median of means | rel. RMSE | >10x ref | dropped | s |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
}

// c == nullptr: the reference's own row.
inline void printRow(const std::string& caseName, const std::string& method, const StabilityRun& run,
                     const Comparison* c) {
    printHeader();
    std::printf("| %s | %s | %d | ", caseName.c_str(), method.c_str(), run.sppPerBatch * run.batches);
    if (c)
        std::printf("%.2f | %+.2f | %+.4f | %+.4f | %.4f | %.4f | ", c->maxZ, c->zMean, c->relBias, c->relMedianOfMeans,
                    c->relRmse, c->outliers);
    else
        std::printf("- | - | - | - | - | - | ");
    std::printf("%llu | %.1f |\n", (unsigned long long)run.nonFinite, run.seconds);
    std::fflush(stdout);
}

inline void printCost(const std::string& caseName, const std::string& method, double ratio) {
    printHeader();
    std::printf("| %s | %s | cost per sample %.1fx the twin's | | | | | | | | |\n", caseName.c_str(), method.c_str(), ratio);
    std::fflush(stdout);
}

}  // namespace brume::test
