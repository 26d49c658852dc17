// The preview size while the user drags something: each frame has a time budget (>= 30 fps);
// converging frames spend it through Renderer::renderFor (whole samples, or a band of rows of one),
// but a drag wants the whole image updated every frame, so when one full-resolution sample would
// not fit the budget the pacer turns the measured cost into a resolution divisor for a preview.
#pragma once

namespace caustic::editor {

class FramePacer {
public:
    static constexpr int kMaxDivisor = 8;

    // The measured cost of `samples` samples per pixel at `pixels` pixels.
    void record(int samples, long long pixels, double seconds);
    bool measured() const { return m_secondsPerSamplePixel > 0.0; }
    double secondsPerSample(long long pixels) const { return m_secondsPerSamplePixel * double(pixels); }

    // The smallest divisor d of 1, 2, 4, 8 (1 = full resolution) for which one sample of the image
    // shrunk by d in each direction fits in budgetSeconds. Powers of two, so that the refinement
    // after an edit, which halves it, goes 1/8 -> 1/4 -> 1/2 -> 1 (render_session.cpp).
    int previewDivisor(long long pixels, double budgetSeconds) const;

private:
    double m_secondsPerSamplePixel = 0.0;   // exponential moving average
};

}  // namespace caustic::editor
