#include "renderer/film.h"

namespace caustic {

Film resolveFilm(const Accumulators& a) {
    Film film;
    film.width = a.width;
    film.height = a.height;
    const size_t n = static_cast<size_t>(a.width) * a.height;
    film.mean.resize(n);
    film.varianceOfMean.resize(n);
    film.count.resize(n);
    film.albedo.resize(n);
    film.normal.resize(n);
    for (size_t i = 0; i < n; ++i) {
        // The AOVs count every sample, dropped ones too (path.comp), so they have their own count.
        if (a.albedo[i].a > 0.0f) film.albedo[i] = glm::vec3(a.albedo[i]) / a.albedo[i].a;
        if (a.normal[i].a > 0.0f) film.normal[i] = glm::vec3(a.normal[i]) / a.normal[i].a;
        const float c = a.sum[i].a;
        film.count[i] = c;
        if (c <= 0.0f) continue;
        const glm::vec3 mean = glm::vec3(a.sum[i]) / c;
        film.mean[i] = mean;
        if (c > 1.0f) {
            const glm::vec3 var = (glm::vec3(a.sumSq[i]) - c * mean * mean) / (c - 1.0f);
            film.varianceOfMean[i] = glm::max(var, glm::vec3(0.0f)) / c;
        }
    }
    return film;
}

}  // namespace caustic
