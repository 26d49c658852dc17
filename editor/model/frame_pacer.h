// How much to render per UI frame so the editor stays responsive (>= 30 fps): the renderer is
// synchronous (Renderer::render(n) returns when n samples per pixel are done), so each frame gets
// a time budget and the pacer turns the measured cost of one sample into a sample count, or,
// when even one full-resolution sample would blow the budget while the user drags something,
// into a resolution divisor for a quick preview.
#pragma once

namespace caustic::editor {

class FramePacer {
public:
    static constexpr int kMaxSamplesPerFrame = 64;
    static constexpr int kMaxDivisor = 8;

    // The measured cost of `samples` samples per pixel at `pixels` pixels.
    void record(int samples, long long pixels, double seconds);
    bool measured() const { return m_secondsPerSamplePixel > 0.0; }
    double secondsPerSample(long long pixels) const { return m_secondsPerSamplePixel * double(pixels); }

    // Samples to render this frame within budgetSeconds (at least 1: progress never stops).
    int samplesForFrame(long long pixels, double budgetSeconds) const;
    // The smallest divisor d (1 = full resolution) for which one sample of the image shrunk by
    // d in each direction fits in budgetSeconds.
    int previewDivisor(long long pixels, double budgetSeconds) const;

private:
    double m_secondsPerSamplePixel = 0.0;   // exponential moving average
};

}  // namespace caustic::editor
