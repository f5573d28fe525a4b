#pragma once
// NCCL, loaded at run time. libnccl is large (about 200 MB) and only the nccl transport needs
// it, so the solver does not link it: the first NcclCommunicators opens libnccl.so.2 with
// dlopen and says clearly when it is not there. Types come from the toolkit's nccl.h.
#include <dlfcn.h>

#include <string>
#include <vector>

#include "backend/cuda_check.cuh"
#include "core/error.hpp"

#if __has_include(<nccl.h>)
#include <nccl.h>
#define SPH_HAVE_NCCL_HEADER 1
#endif

namespace sph {

#ifdef SPH_HAVE_NCCL_HEADER

// The entry points this project uses, resolved once.
struct NcclApi {
    ncclResult_t (*comm_init_all)(ncclComm_t*, int, const int*) = nullptr;
    ncclResult_t (*comm_destroy)(ncclComm_t) = nullptr;
    ncclResult_t (*group_start)() = nullptr;
    ncclResult_t (*group_end)() = nullptr;
    ncclResult_t (*send)(const void*, size_t, ncclDataType_t, int, ncclComm_t, cudaStream_t) = nullptr;
    ncclResult_t (*recv)(void*, size_t, ncclDataType_t, int, ncclComm_t, cudaStream_t) = nullptr;
    const char* (*error_string)(ncclResult_t) = nullptr;

    static const NcclApi& get() {
        static const NcclApi api = load();
        return api;
    }
    void check(ncclResult_t r, const char* what) const {
        if (r != ncclSuccess) throw RunError(std::string("NCCL ") + what + " failed: " + error_string(r));
    }

private:
    static NcclApi load() {
        void* lib = dlopen("libnccl.so.2", RTLD_NOW | RTLD_LOCAL);
        if (!lib) lib = dlopen("libnccl.so", RTLD_NOW | RTLD_LOCAL);
        if (!lib)
            throw InputError("the nccl transport needs libnccl.so.2, which the dynamic loader cannot find (" +
                             std::string(dlerror()) + "); install NCCL or use --transport peer");
        NcclApi a;
        bind(lib, a.comm_init_all, "ncclCommInitAll");
        bind(lib, a.comm_destroy, "ncclCommDestroy");
        bind(lib, a.group_start, "ncclGroupStart");
        bind(lib, a.group_end, "ncclGroupEnd");
        bind(lib, a.send, "ncclSend");
        bind(lib, a.recv, "ncclRecv");
        bind(lib, a.error_string, "ncclGetErrorString");
        return a;  // the library stays loaded for the life of the process
    }
    template <class F>
    static void bind(void* lib, F& f, const char* symbol) {
        f = reinterpret_cast<F>(dlsym(lib, symbol));
        if (!f) throw InputError(std::string("libnccl lacks ") + symbol + " (NCCL 2.7 or newer is needed for send/receive)");
    }
};

// One communicator per rank (rank d = subdomain d on devices[d]), all in this process.
class NcclCommunicators {
public:
    NcclCommunicators() = default;
    explicit NcclCommunicators(const std::vector<int>& devices) : comms_(devices.size(), nullptr) {
        const NcclApi& api = NcclApi::get();
        api.check(api.comm_init_all(comms_.data(), int(devices.size()), devices.data()), "ncclCommInitAll");
    }
    NcclCommunicators(NcclCommunicators&& o) noexcept : comms_(std::move(o.comms_)) { o.comms_.clear(); }
    NcclCommunicators& operator=(NcclCommunicators&& o) noexcept {
        std::swap(comms_, o.comms_);
        return *this;
    }
    ~NcclCommunicators() {
        for (ncclComm_t c : comms_)
            if (c) NcclApi::get().comm_destroy(c);  // unchecked: destructors must not throw
    }
    // Sends and receives between these two run as one operation.
    void begin_group() const { NcclApi::get().check(NcclApi::get().group_start(), "ncclGroupStart"); }
    void end_group() const { NcclApi::get().check(NcclApi::get().group_end(), "ncclGroupEnd"); }
    void send(int rank, const void* data, std::size_t bytes, int peer, cudaStream_t s) const {
        const NcclApi& api = NcclApi::get();
        api.check(api.send(data, bytes, ncclUint8, peer, comms_[rank], s), "ncclSend");
    }
    void receive(int rank, void* data, std::size_t bytes, int peer, cudaStream_t s) const {
        const NcclApi& api = NcclApi::get();
        api.check(api.recv(data, bytes, ncclUint8, peer, comms_[rank], s), "ncclRecv");
    }

private:
    std::vector<ncclComm_t> comms_;
};

#else

struct NcclCommunicators {
    NcclCommunicators() = default;
    explicit NcclCommunicators(const std::vector<int>&) {
        throw InputError("this build has no NCCL headers (nccl.h), so the nccl transport is unavailable; use --transport peer");
    }
    void begin_group() const {}
    void end_group() const {}
    void send(int, const void*, std::size_t, int, cudaStream_t) const {}
    void receive(int, void*, std::size_t, int, cudaStream_t) const {}
};

#endif

}  // namespace sph
