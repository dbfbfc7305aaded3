#pragma once
// OpenMesh logs through global streams; they are silenced while it works for us (its complaints
// are turned into our own errors, or into a fallback) and restored afterwards. The streams are
// the process's: one QuietOpenMesh at a time (a mesh read and the prism walk's merge may run on
// different threads in the viewer).
#include <OpenMesh/Core/System/omstream.hh>

#include <mutex>

namespace pr {

class QuietOpenMesh {
public:
    QuietOpenMesh()
        : lock_(mutex()), err_(::omerr().is_enabled()), out_(::omout().is_enabled()), log_(::omlog().is_enabled())
    {
        ::omerr().disable();
        ::omout().disable();
        ::omlog().disable();
    }
    ~QuietOpenMesh()
    {
        if (err_) ::omerr().enable();
        if (out_) ::omout().enable();
        if (log_) ::omlog().enable();
    }
    QuietOpenMesh(const QuietOpenMesh&) = delete;
    QuietOpenMesh& operator=(const QuietOpenMesh&) = delete;

private:
    static std::mutex& mutex()
    {
        static std::mutex m;
        return m;
    }
    std::lock_guard<std::mutex> lock_;
    bool err_, out_, log_;
};

} // namespace pr
