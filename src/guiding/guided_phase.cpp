#include "brume/guiding/guided_phase.h"

namespace brume {

GuidedPhase GuidedPhase::at(const GuidingField* field, Vec3 p, Vec3 d, float g) {
    GuidedPhase gp;
    gp.d = d;
    gp.g = g;
    if (!field) return gp;
    const GuidingCell* cell = field->lookup(p);
    gp.cell = cell;
    if (!cell || !(cell->share > 0)) return gp;  // (a cell may guide surface vertices only)
    if (vmfProduct(cell->medium, hgAsVmf(d, g), &gp.product)) gp.share = cell->share;
    return gp;
}

}  // namespace brume
