// `--guiding auto` (the default; docs/path-guiding.md, "When the default guides"): when a
// path tracer that renders without a guide starts one. A guide costs its 16 training passes
// (walks that record, early fits) before it pays, so it starts only where at least
// kAutoPasses passes are still to come: with the render's passes known (`--spp`), from the
// pass index; under a time budget, from the time left at the pace of the last pass (so a
// time-budgeted render starts it after its first pass at the earliest; its pass count
// depends on the machine anyway); under a target error for the whole image (`--target-error`,
// `brume render`'s default rule), from the length the film's noise estimate predicts
// (Integrator::expectPasses; not before it predicts one, from 4 passes on). Where none is
// known (a library caller's render of unknown length) it does not start. Nor with fewer than two scattering events (--max-depth
// 0 or 1): after the one event there is nothing left to guide but the phase-sampled hit of
// an emitter, which next-event estimation already covers, while the training and guided
// survival cost (thin fog, a point light in view, single scattering: 0.65× at 10 s, 0.34× at
// 256 spp with `--guiding on`; in full transport the same scene gains 1.7×).
//
// Measured (docs/results.md, "The default guides the path tracer it chooses"; 160×120, 10 s):
// auto 1.15–1.52× as efficient where it guided (campfire, street, cumulus, two validation
// scenes), pt 0.89–1.69× (geometric mean 1.17 over nine scenes). A rule, not a measurement:
// the planner does not rate guiding against its other candidates, and the guide starts only
// where the path tracer is chosen for good.
#pragma once
#include "brume/integrators/integrator.h"

namespace brume {

class GuideStart {
public:
    static constexpr int kAutoPasses = 64;  // passes still to come, the training passes included

    GuideStart(int plannedPasses, int maxDepth) : planned_(plannedPasses), events_(maxDepth) {}
    // Every complete pass of the render (its wall time and budget; PassSummary).
    void endPass(const PassSummary& s) {
        if (!s.complete) return;
        seconds_ += s.seconds;
        last_ = s.seconds;
        budget_ = s.timeBudget;
    }
    // The render's expected length in passes under a target error (−1: not yet estimated).
    void expect(int total) { expected_ = total < 0 ? -1 : total; }
    // Whether a guide started before pass `pass` would have kAutoPasses passes to train and pay.
    bool pays(int pass) const {
        if (events_ >= 0 && events_ < 2) return false;
        if (expected_ != 0) return expected_ - pass >= kAutoPasses;
        if (planned_ > 0) return planned_ - pass >= kAutoPasses;
        if (budget_ > 0 && last_ > 0) return (budget_ - seconds_) / last_ >= kAutoPasses;
        return false;
    }

private:
    int planned_;
    int events_;  // --max-depth (−1: unlimited)
    int expected_ = 0;  // expect(): 0 not given, −1 not yet estimated
    double seconds_ = 0, last_ = 0, budget_ = 0;
};

}  // namespace brume
