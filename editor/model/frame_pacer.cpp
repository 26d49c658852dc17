#include "editor/model/frame_pacer.h"

#include <algorithm>
#include <cmath>

namespace caustic::editor {

void FramePacer::record(int samples, long long pixels, double seconds) {
    if (samples <= 0 || pixels <= 0 || !(seconds > 0.0)) return;
    const double v = seconds / (double(samples) * double(pixels));
    // Quick to follow a slower scene (an edit made it heavier), smooth otherwise.
    const double alpha = v > m_secondsPerSamplePixel ? 0.6 : 0.3;
    m_secondsPerSamplePixel = m_secondsPerSamplePixel == 0.0 ? v : (1.0 - alpha) * m_secondsPerSamplePixel + alpha * v;
}

int FramePacer::previewDivisor(long long pixels, double budgetSeconds) const {
    if (!measured()) return 1;
    for (int d = 1; d < kMaxDivisor; d *= 2)
        if (secondsPerSample(pixels) / double(d * d) <= budgetSeconds) return d;
    return kMaxDivisor;
}

}  // namespace caustic::editor
