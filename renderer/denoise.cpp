#include "renderer/denoise.h"

#ifdef CAUSTIC_HAVE_OIDN
#include <OpenImageDenoise/oidn.hpp>

#include <mutex>
#endif

namespace caustic {

#ifndef CAUSTIC_HAVE_OIDN

bool denoiserAvailable() { return false; }
std::string denoiserVersion() { return "not built"; }

bool denoise(const Film&, const DenoiseOptions&, DenoiseResult*, std::string* error) {
    *error = "this build has no Open Image Denoise (run ./setup.sh, which downloads it into .deps/oidn, "
             "then rebuild)";
    return false;
}

#else

namespace {

std::string deviceTypeName(int type) {
    switch (static_cast<oidn::DeviceType>(type)) {
    case oidn::DeviceType::CPU: return "CPU";
    case oidn::DeviceType::SYCL: return "SYCL";
    case oidn::DeviceType::CUDA: return "CUDA";
    case oidn::DeviceType::HIP: return "HIP";
    case oidn::DeviceType::Metal: return "Metal";
    default: return "unknown";
    }
}

// The name of the first physical device of this type, for the report (one GPU or one CPU here).
std::string physicalDeviceName(int type) {
    for (int i = 0; i < oidn::getNumPhysicalDevices(); ++i) {
        oidn::PhysicalDeviceRef p(i);
        if (p.get<int>("type") == type) return p.get<std::string>("name");
    }
    return "";
}

bool check(oidn::DeviceRef& device, const char* what, std::string* error) {
    const char* message = nullptr;
    if (device.getError(message) == oidn::Error::None) return true;
    *error = std::string("Open Image Denoise: ") + what + ": " + (message ? message : "unknown error");
    return false;
}

}  // namespace

bool denoiserAvailable() { return true; }
std::string denoiserVersion() { return OIDN_VERSION_STRING; }

bool denoise(const Film& film, const DenoiseOptions& options, DenoiseResult* out, std::string* error) {
    const size_t n = static_cast<size_t>(film.width) * film.height;
    if (n == 0 || film.mean.size() != n) {
        *error = "denoise: the film is empty";
        return false;
    }
    const bool guides = options.useGuides && film.albedo.size() == n && film.normal.size() == n;
    const size_t bytes = n * sizeof(glm::vec3);
    const auto w = static_cast<size_t>(film.width), h = static_cast<size_t>(film.height);

    // The default device is the fastest one present: CUDA on an NVIDIA machine, else the CPU
    // (without CUDA its module fails to load quietly). Buffers made by the device and filled
    // with write() work on every device type, host-visible or not.
    // The device is made once and kept: creating one (a CUDA context, thread pools) cost about a
    // quarter of a second per call on the H100 (docs/performance.md). Calls are serialised by a
    // mutex (the editor denoises on a worker thread, batch mode on the main thread).
    // Never destroyed: releasing a CUDA device from a static destructor, after the driver may
    // have shut down, is a crash at exit waiting to happen; the process's end frees it.
    static std::mutex mutex;
    static oidn::DeviceRef& device = *new oidn::DeviceRef();
    static std::string deviceName;
    std::lock_guard<std::mutex> lock(mutex);
    if (!device) {
        device = oidn::newDevice(oidn::DeviceType::Default);
        if (!device) {
            *error = "Open Image Denoise: no device could be created";
            return false;
        }
        device.commit();
        if (!check(device, "device", error)) {
            device = oidn::DeviceRef();
            return false;
        }
        const int type = device.get<int>("type");
        deviceName = deviceTypeName(type);
        if (std::string name = physicalDeviceName(type); !name.empty()) deviceName += " (" + name + ")";
    }
    out->device = deviceName;

    oidn::BufferRef color = device.newBuffer(bytes), output = device.newBuffer(bytes);
    color.write(0, bytes, film.mean.data());
    oidn::BufferRef albedo, normal;
    if (guides) {
        albedo = device.newBuffer(bytes);
        normal = device.newBuffer(bytes);
        albedo.write(0, bytes, film.albedo.data());
        normal.write(0, bytes, film.normal.data());
    }
    if (!check(device, "buffers", error)) return false;

    if (guides && options.prefilterGuides) {
        // Prefilter each guide in place with the RT filter (OIDN docs, "Denoising with
        // prefiltering"): albedo alone, then normal alone.
        for (auto [name, buffer] : {std::pair{"albedo", &albedo}, std::pair{"normal", &normal}}) {
            oidn::FilterRef pre = device.newFilter("RT");
            pre.setImage(name, *buffer, oidn::Format::Float3, w, h);
            pre.setImage("output", *buffer, oidn::Format::Float3, w, h);
            pre.commit();
            pre.execute();
            if (!check(device, name, error)) return false;
        }
    }

    oidn::FilterRef filter = device.newFilter("RT");
    filter.setImage("color", color, oidn::Format::Float3, w, h);
    if (guides) {
        filter.setImage("albedo", albedo, oidn::Format::Float3, w, h);
        filter.setImage("normal", normal, oidn::Format::Float3, w, h);
        filter.set("cleanAux", options.prefilterGuides);
    }
    filter.setImage("output", output, oidn::Format::Float3, w, h);
    filter.set("hdr", true);
    filter.commit();
    filter.execute();
    if (!check(device, "filter", error)) return false;
    out->image.resize(n);
    output.read(0, bytes, out->image.data());
    return check(device, "read back", error);
}

#endif

}  // namespace caustic
