// Cone maps on the GPU: uploads the max pyramid, runs shaders/conemap.comp in chunks, reads the
// integer steps back. See render/conemap_gpu.hpp.
#include "render/conemap_gpu.hpp"

#include "core/error.hpp"
#include "gl/objects.hpp"
#include "render/shader_program.hpp"

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstring>
#include <exception>
#include <numeric>
#include <string>
#include <system_error>
#include <thread>

namespace pr {

namespace {

constexpr int kMaxLevels = 16;     // PR_CONE_MAX_LEVELS in conemap.comp
constexpr GLuint kGroupSize = 64;  // local_size_x in conemap.comp
// Texels per dispatch: the first few small (pathological maps take long per texel), the next
// sized from the time of the one before to take about kChunkSeconds. Each dispatch ends with a
// wait while its last groups finish on one core, so fewer, longer ones are faster (16384 texels
// at a time cost llvmpipe 8 % on a 1024² map); but none runs for long, and the progress moves.
// At most 2^19 texels: at most 2^16 pieces (of at least eight texels), whose spread order
// (spread_step) the shader computes in 32 bits.
constexpr std::size_t kFirstChunkTexels = 16384;
constexpr std::size_t kMaxChunkTexels = std::size_t(1) << 19;
constexpr double kChunkSeconds = 0.25;
constexpr std::size_t kResumeWords = 17; // conemap.comp, save_search
constexpr std::size_t kDefaultResumeCapacity = 32768;

// The searches the GPU left to the CPU in one dispatch (conemap.comp, b_resume), as
// maps::ConeSearchState.
std::vector<ConeSearchState> read_searches(const std::vector<std::uint32_t>& words, std::size_t count)
{
    std::vector<ConeSearchState> states(count);
    for (std::size_t e = 0; e < count; ++e) {
        const std::uint32_t* w = words.data() + e * kResumeWords;
        ConeSearchState& s = states[e];
        s.texel = w[0];
        s.relaxed = w[1] != 0;
        s.filled = w[2];
        s.last_level = int(w[3]);
        s.last_i = int(w[4]);
        s.last_j = int(w[5]);
        const std::uint64_t bits = std::uint64_t(w[6]) | (std::uint64_t(w[7]) << 32);
        std::memcpy(&s.best, &bits, sizeof s.best);
        s.march_budget = int(w[8]);
        for (int l = 0; l < 16; ++l) s.lists[l] = (w[9 + l / 2] >> (16 * (l % 2))) & 0xffffu;
    }
    return states;
}

// The texels (or seeds) the dispatch after one of `count` that took `seconds` takes: about
// kChunkSeconds at its pace, growing at most fourfold, at most `most`, in whole groups.
// In whole `unit`s (the texel dispatches: whole pairs of rows where they go in blocks).
std::size_t next_chunk(std::size_t count, double seconds, std::size_t most, std::size_t unit = kGroupSize)
{
    const double scale = seconds > 0.0 ? std::clamp(kChunkSeconds / seconds, 0.25, 4.0) : 4.0;
    return std::clamp(std::size_t(double(count) * scale) / unit * unit, unit, std::max(most / unit * unit, unit));
}

// The step of a texel dispatch's spread order (conemap.comp, u_spread) over its `pieces` whole
// pieces (pairs of rows where texels go in blocks, else runs of 64 texels): near the golden
// ratio's fraction of them and coprime to their count, so that every contiguous share of the
// order takes pieces evenly from the whole dispatch. llvmpipe splits a dispatch's groups into one
// contiguous share per thread (lp_cs_tpool: groups / threads each, the remainder one by one), so
// with the rows in order one thread took rows costlier than the other's and the other waited:
// builtin:bricks@512, relaxed, one core idle for 10-25 % of each dispatch (perf, every CPU
// sampled). Pieces smaller than a pair of rows (a block each) were slower: a group's lanes then
// read far apart.
GLuint spread_step(std::size_t pieces)
{
    if (pieces < 3) return 1;
    std::size_t step = std::max<std::size_t>(1, std::size_t(0.6180339887498949 * double(pieces)));
    while (std::gcd(step, pieces) != 1) ++step;
    return GLuint(step);
}

// The seeds found by the CPU's threads (maps::cone_seeds_cpu) while the calling thread makes the
// context and compiles the shader, one thread's work: on two cores the other core idled for
// about 85 ms there, and the seeds (about 190 ms of core time for builtin:bricks@512, relaxed)
// waited for it. They run at the usual priority (at the lowest, nice 19, a build on a loaded
// machine would wait for them for as long as the load lasts: a thread cannot raise its priority
// again): while the context is made three threads share the two cores, no core idles, and the
// caller waits for them (take) only after the compile. stop() (and the destructor, on every way
// out) cancels them and waits. Threads started while Mesa loads (preload_backend) start once it
// has loaded (glibc's pthread_create waits for a dlopen in progress).
class EarlySeeds {
public:
    EarlySeeds() = default;
    EarlySeeds(const EarlySeeds&) = delete;
    EarlySeeds& operator=(const EarlySeeds&) = delete;
    ~EarlySeeds() { stop(); }

    void start(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind, const ConeBuildOptions& options)
    {
        ConeBuildOptions part = options;
        part.progress = [this](double f) { fraction_.store(f, std::memory_order_relaxed); }; // (take() reports it)
        part.cancel = &stop_;
        try {
            thread_ = std::thread([this, &field, &pyramid, kind, part] {
                try {
                    seeds_ = cone_seeds_cpu(field, pyramid, kind, part);
                } catch (...) {
                    error_ = std::current_exception();
                }
                done_.store(true, std::memory_order_release);
            });
        } catch (const std::system_error&) {
            // (No thread to be had: take() finds them on the caller's thread.)
        }
    }

    // The seeds (rethrows what their search threw: ConeBuildCancelled where the build's cancel
    // flag turned true meanwhile). Where start() had no thread, found now, on the CPU's threads
    // as usual. options.progress is called from this thread with their share of the progress.
    ConeSeeds take(const HeightField& field, const MaxPyramid& pyramid, ConeKind kind, const ConeBuildOptions& options)
    {
        if (!thread_.joinable()) {
            ConeBuildOptions part = options;
            if (options.progress) part.progress = [&](double f) { options.progress(kConeSeedProgress * f); };
            return cone_seeds_cpu(field, pyramid, kind, part);
        }
        // The build's cancel flag is passed on while waiting (the seeds' own flag is stop_).
        auto reported = std::chrono::steady_clock::now();
        while (!done_.load(std::memory_order_acquire)) {
            if (options.cancel && options.cancel->load(std::memory_order_relaxed)) stop_.store(true);
            std::this_thread::sleep_for(std::chrono::microseconds(200));
            if (options.progress && std::chrono::steady_clock::now() - reported > std::chrono::milliseconds(100)) {
                options.progress(kConeSeedProgress * fraction_.load(std::memory_order_relaxed));
                reported = std::chrono::steady_clock::now();
            }
        }
        thread_.join();
        if (error_) std::rethrow_exception(error_);
        if (options.progress) options.progress(kConeSeedProgress);
        return std::move(seeds_);
    }

    // Still finding them (started, on a thread of their own, and not done).
    bool busy() const { return thread_.joinable() && !done_.load(std::memory_order_acquire); }

    void stop()
    {
        if (!thread_.joinable()) return;
        stop_.store(true);
        thread_.join();
    }

private:
    std::thread thread_;
    std::atomic<bool> stop_{false};
    std::atomic<bool> done_{false};
    std::atomic<double> fraction_{0.0};
    ConeSeeds seeds_;
    std::exception_ptr error_;
};

} // namespace

ConeMap build_cone_map_gpu(const HeightField& given, ConeKind kind, const ConeBuildOptions& options,
                           ConeGpuReport* report, const std::function<void()>& make_current)
{
    const std::string subject = given.name.empty() ? "height map" : given.name; // for error lines
    const std::size_t n = std::size_t(std::max(given.width, 0)) * std::size_t(std::max(given.height, 0));
    if (n == 0 || given.texels.size() != n) throw Error(subject, "cannot build a cone map of an empty height field");
    // The heights the map stores (rg8: rounded to 8 bits), as the CPU generator does.
    HeightField rounded;
    const HeightField& field = cone_source_field(given, options.format, rounded);
    const MaxPyramid pyramid = build_max_pyramid(field);
    if (pyramid.levels() > kMaxLevels) throw Error(subject, "height map too large for the GPU generator");
    if (pyramid.data.size() > std::size_t(1) << 30) throw Error(subject, "height map too large for the GPU generator");

    // The children of every node above level 0, four maxima in one vec4 (conemap.comp, Groups).
    int group_offset[kMaxLevels] = {};
    std::size_t nodes = 0; // above level 0
    for (int l = 0; l + 1 < pyramid.levels(); ++l) {
        group_offset[l] = int(nodes);
        nodes += std::size_t(pyramid.widths[std::size_t(l + 1)]) * std::size_t(pyramid.heights[std::size_t(l + 1)]);
    }
    std::vector<float> groups(4 * std::max<std::size_t>(nodes, 1), -1.0f); // a single texel: no children anywhere
    for (int l = 0; l + 1 < pyramid.levels(); ++l) {
        const int w = pyramid.widths[std::size_t(l)], h = pyramid.heights[std::size_t(l)];
        const int pw = pyramid.widths[std::size_t(l + 1)], ph = pyramid.heights[std::size_t(l + 1)];
        const float* level = pyramid.data.data() + pyramid.offsets[std::size_t(l)];
        float* out = groups.data() + 4 * std::size_t(group_offset[l]);
        for (int j = 0; j < ph; ++j)
            for (int i = 0; i < pw; ++i, out += 4)
                for (int q = 0; q < 4; ++q) {
                    const int ci = 2 * i + (q & 1), cj = 2 * j + (q >> 1);
                    if (ci < w && cj < h) out[q] = level[std::size_t(cj) * std::size_t(w) + std::size_t(ci)];
                }
    }
    // Unless the shader is to find them, the CPU's threads start on the seeds now (EarlySeeds),
    // while this thread makes the context and compiles the shader.
    EarlySeeds early;
    if (options.gpu_seed_pass != ConeBuildOptions::SeedPass::Gpu) early.start(field, pyramid, kind, options);
    if (make_current) make_current();
    while (glGetError() != GL_NO_ERROR) {} // errors of earlier work are not ours
    gl::Buffer data = gl::immutable_buffer(pyramid.data);
    gl::Buffer children = gl::immutable_buffer(groups);
    // Read as buffer textures where they fit (conemap.comp), else as storage buffers.
    GLint64 max_texels = 0;
    glGetInteger64v(GL_MAX_TEXTURE_BUFFER_SIZE, &max_texels);
    const bool texels = !options.gpu_storage_buffers && GLint64(pyramid.data.size()) <= max_texels &&
                        GLint64(groups.size() / 4) <= max_texels;
    ShaderDefines defines{{"PR_CONE_KIND", kind == ConeKind::Relaxed ? "1" : "0"}};
    if (!texels) defines.emplace_back("PR_CONE_BUFFERS", "1");
    gl::Program program = build_program({{GL_COMPUTE_SHADER, "conemap.comp"}}, defines);
    gl::Texture data_texels, children_texels;
    // The relaxed march's bilinear heights (conemap.comp, bilinear): level 0 as a 2D texture,
    // whose textureGather brings a sample's four texels, wrapped, in one fetch.
    gl::Texture heights_2d;
    if (kind == ConeKind::Relaxed) {
        heights_2d = gl::map_texture(GL_R32F, field.width, field.height, GL_RED, pyramid.data.data(), GL_NEAREST);
        if (glGetError() == GL_OUT_OF_MEMORY)
            throw Error(subject, "out of GPU memory for the heights of the GPU generator's relaxed march");
    }
    if (texels) {
        data_texels = gl::Texture::create(GL_TEXTURE_BUFFER);
        glTextureBuffer(data_texels.id(), GL_R32F, data.id());
        children_texels = gl::Texture::create(GL_TEXTURE_BUFFER);
        glTextureBuffer(children_texels.id(), GL_RGBA32F, children.id());
    }
    gl::Buffer steps = gl::Buffer::create();
    glNamedBufferStorage(steps.id(), GLsizeiptr(n * sizeof(std::uint32_t)), nullptr, 0);
    // The searches that ran out of nodes: a count, then their states (conemap.comp, b_resume).
    const std::size_t capacity =
        options.gpu_resume_capacity > 0 ? std::size_t(options.gpu_resume_capacity) : kDefaultResumeCapacity;
    gl::Buffer resume = gl::Buffer::create();
    glNamedBufferStorage(resume.id(), GLsizeiptr((1 + capacity * kResumeWords) * sizeof(std::uint32_t)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);
    // The seeds (maps::cone_seeds_cpu's, found below): the cone seeds, then kind relaxed's relaxed ones.
    ConeSeeds seeds = cone_seed_grid(field, kind);
    const std::size_t seed_count = seeds.texels.size();
    const bool relaxed = kind == ConeKind::Relaxed;
    gl::Buffer seed_buffer = gl::Buffer::create();
    glNamedBufferStorage(seed_buffer.id(), GLsizeiptr((relaxed ? 2 : 1) * seed_count * sizeof(std::uint32_t)), nullptr,
                         GL_DYNAMIC_STORAGE_BIT);

    const GLuint p = program.id();
    glProgramUniform2i(p, 0, field.width, field.height);
    glProgramUniform1i(p, 1, pyramid.levels());
    glProgramUniform1i(p, 2, cone_format_steps(options.format));
    glProgramUniform1i(p, 5, options.relaxed_budget > 0 ? options.relaxed_budget : 0x7fffffff);
    glProgramUniform1i(p, 6, options.node_budget > 0 ? options.node_budget : 0x7fffffff);
    glProgramUniform1ui(p, 7, GLuint(capacity));
    int w[kMaxLevels] = {}, h[kMaxLevels] = {}, off[kMaxLevels] = {};
    for (int l = 0; l < pyramid.levels(); ++l) {
        w[l] = pyramid.widths[std::size_t(l)];
        h[l] = pyramid.heights[std::size_t(l)];
        off[l] = int(pyramid.offsets[std::size_t(l)]);
    }
    glProgramUniform1iv(p, 8, kMaxLevels, w);
    glProgramUniform1iv(p, 24, kMaxLevels, h);
    glProgramUniform1iv(p, 40, kMaxLevels, off);
    glProgramUniform1iv(p, 56, kMaxLevels, group_offset);
    glProgramUniform2i(p, 72, seeds.width, seeds.height);

    glUseProgram(p);
    // Everything bound here is unbound (to 0) on every way out, a CPU share that throws too (a
    // cancelled build, ConeBuildOptions::cancel; memory): nothing of the build stays bound.
    struct Unbind {
        ~Unbind()
        {
            for (GLuint b : {0u, 1u, 2u, 3u, 4u}) glBindBufferBase(GL_SHADER_STORAGE_BUFFER, b, 0);
            glBindTextureUnit(0, 0);
            glBindTextureUnit(1, 0);
            glBindTextureUnit(2, 0);
            glUseProgram(0);
        }
    } unbind;
    if (texels) {
        glBindTextureUnit(0, data_texels.id());
        glBindTextureUnit(1, children_texels.id());
    } else {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, data.id());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 2, children.id());
    }
    if (heights_2d) glBindTextureUnit(2, heights_2d.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, steps.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, resume.id());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, seed_buffer.id());
    const auto search_start = std::chrono::steady_clock::now();
    // The seeds first (maps::ConeSeeds; conemap.comp, u_seeding): the coarse ones, then the others
    // from them; a sixteenth of the searches, their share of the progress. On a software renderer
    // the CPU's threads find them (ConeBuildOptions::gpu_seed_pass), else the shader, whose seeds
    // are read back for the CPU's share of the searches below.
    bool cpu_seeds = options.gpu_seed_pass == ConeBuildOptions::SeedPass::Cpu;
    if (options.gpu_seed_pass == ConeBuildOptions::SeedPass::Auto) {
        const auto* renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
        const std::string name = renderer ? renderer : "";
        cpu_seeds = name.find("llvmpipe") != std::string::npos || name.find("softpipe") != std::string::npos ||
                    name.find("swrast") != std::string::npos;
    }
    std::size_t chunk = kFirstChunkTexels / (kConeSeedSpacing * kConeSeedSpacing);
    // In the buffer as x | y << 16 (conemap.comp, Seeds), in ConeSeeds as y * width + x.
    const auto seed_words = [&](bool of_relaxed) {
        return std::pair{GLintptr((of_relaxed ? seed_count : 0) * sizeof(std::uint32_t)),
                         GLsizeiptr(seed_count * sizeof(std::uint32_t))};
    };
    const std::uint32_t row = std::uint32_t(field.width);
    if (!cpu_seeds) early.stop(); // (a GPU renderer's shader finds them, below)
    if (cpu_seeds) {
        // llvmpipe makes the shader's code at its first dispatch (from Mesa's cache: 11-20 ms of
        // this thread, while a core idled in the first texel dispatch): where the seeds' threads
        // still run, an empty dispatch (no texel: u_count 0) makes it now, beside them.
        // (builtin:bricks@512, relaxed, alternated: 775 ms against 801, median of five.)
        if (early.busy()) {
            glProgramUniform1ui(p, 3, 0u);
            glProgramUniform1ui(p, 4, 0u);
            glDispatchCompute(1, 1, 1);
            glFinish();
        }
        seeds = early.take(field, pyramid, kind, options);
        for (const bool of_relaxed : {false, true}) {
            if (of_relaxed && !relaxed) break;
            const auto [offset, size] = seed_words(of_relaxed);
            std::vector<std::uint32_t> packed = of_relaxed ? seeds.relaxed : seeds.texels;
            for (std::uint32_t& t : packed)
                if (t != kNoConeSeed) t = (t % row) | ((t / row) << 16);
            glNamedBufferSubData(seed_buffer.id(), offset, size, packed.data());
        }
    } else {
        // As the CPU's: the cone seeds, then the relaxed ones; of each, the coarse seeds, then the
        // others from them.
        constexpr int stride = 1 << (kCoarseSeedShift - kSeedShift);
        const std::size_t coarse_seeds =
            std::size_t((seeds.width + stride - 1) / stride) * std::size_t((seeds.height + stride - 1) / stride);
        for (const bool of_relaxed : {false, true}) {
            if (of_relaxed && !relaxed) break;
            glProgramUniform1i(p, 74, of_relaxed ? 1 : 0);
            for (const int pass : {2, 1}) {
                glProgramUniform1i(p, 73, pass);
                const std::size_t items = pass == 2 ? coarse_seeds : seed_count;
                const auto [from, share] = cone_seed_pass_progress(kind, of_relaxed, pass == 2);
                for (std::size_t first = 0; first < items;) {
                    if (options.cancel && options.cancel->load(std::memory_order_relaxed)) throw ConeBuildCancelled();
                    const std::size_t count = std::min(chunk, items - first);
                    const auto start = std::chrono::steady_clock::now();
                    glProgramUniform1ui(p, 3, GLuint(first));
                    glProgramUniform1ui(p, 4, GLuint(count));
                    glDispatchCompute(GLuint((count + kGroupSize - 1) / kGroupSize), 1, 1);
                    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT); // (the next pass reads them)
                    glFinish();
                    first += count;
                    if (options.progress)
                        options.progress(kConeSeedProgress * (from + share * double(first) / double(items)));
                    chunk = next_chunk(count,
                                       std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                                       kMaxChunkTexels);
                }
            }
        }
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        for (const bool of_relaxed : {false, true}) {
            if (of_relaxed && !relaxed) break;
            std::vector<std::uint32_t>& out = of_relaxed ? seeds.relaxed : seeds.texels;
            const auto [offset, size] = seed_words(of_relaxed);
            glGetNamedBufferSubData(seed_buffer.id(), offset, size, out.data());
            for (std::uint32_t& t : out)
                if (t != kNoConeSeed) t = (t >> 16) * row + (t & 0xffffu);
        }
    }
    glProgramUniform1i(p, 73, 0);
    const double seed_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - search_start).count();
    // Texels go to the shader's lanes in blocks of 4 x 2 (conemap.comp, u_blocks) where the map's
    // width is a multiple of 4 and its height even, so each dispatch takes whole pairs of rows:
    // the texels of [first, first + count) are those of the rows it covers, in another order.
    const bool blocks = field.width % 4 == 0 && field.height % 2 == 0;
    glProgramUniform1i(p, 75, blocks ? 1 : 0);
    const std::size_t unit = blocks ? 2 * std::size_t(field.width) : kGroupSize;
    chunk = std::max(kFirstChunkTexels / unit, std::size_t(1)) * unit;
    std::vector<std::uint32_t> k(n);
    std::vector<std::uint32_t> words, resumed, again;
    std::vector<int> missing;
    double cpu_seconds = 0.0;
    std::size_t resumed_count = 0, restarted_count = 0;
    constexpr std::uint32_t kRanOut = 0xc0000000u; // conemap.comp: bit 31 cone, bit 30 relaxed search
    for (std::size_t first = 0; first < n;) {
        if (options.cancel && options.cancel->load(std::memory_order_relaxed)) throw ConeBuildCancelled();
        const std::size_t count = std::min(chunk, n - first);
        const auto start = std::chrono::steady_clock::now();
        const GLuint zero = 0;
        glNamedBufferSubData(resume.id(), 0, sizeof zero, &zero);
        glProgramUniform1ui(p, 3, GLuint(first));
        glProgramUniform1ui(p, 4, GLuint(count));
        glProgramUniform1ui(p, 76, spread_step(count / (blocks ? 2 * std::size_t(field.width) : 64)));
        glDispatchCompute(GLuint((count + kGroupSize - 1) / kGroupSize), 1, 1);
        glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
        glGetNamedBufferSubData(steps.id(), GLintptr(first * sizeof(std::uint32_t)),
                                GLsizeiptr(count * sizeof(std::uint32_t)), k.data() + first); // waits for it
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        // Where the node budget ran out, the CPU's search goes on best first (maps::Searcher), so
        // that the map is the CPU generator's: from the GPU's state where it saved one, else
        // from the start (a search the GPU had no room for).
        GLuint saved = 0;
        glGetNamedBufferSubData(resume.id(), 0, sizeof saved, &saved);
        const std::size_t stored = std::min<std::size_t>(saved, capacity);
        words.resize(stored * kResumeWords);
        if (stored > 0)
            glGetNamedBufferSubData(resume.id(), sizeof(GLuint), GLsizeiptr(words.size() * sizeof(std::uint32_t)),
                                    words.data());
        const auto cpu_start = std::chrono::steady_clock::now();
        // Per texel of the chunk, its searches that ran out less those saved: a texel with one
        // missing (no room for it in b_resume) is searched again from the start, the others go on
        // from their saved states.
        missing.assign(count, 0);
        for (std::size_t t = first; t < first + count; ++t) {
            missing[t - first] = std::popcount(k[t] & kRanOut);
            k[t] &= ~kRanOut; // (the low bits: the other search's k, or 0)
        }
        std::vector<ConeSearchState> states = read_searches(words, stored);
        std::erase_if(states, [&](const ConeSearchState& st) {
            return st.texel < first || st.texel >= first + count || missing[st.texel - first]-- <= 0;
        });
        again.clear();
        for (std::size_t t = first; t < first + count; ++t)
            if (missing[t - first] > 0) again.push_back(std::uint32_t(t));
        std::erase_if(states, [&](const ConeSearchState& st) { return missing[st.texel - first] > 0; });
        cone_steps_resumed(field, pyramid, kind, options, seeds, states, resumed);
        for (std::size_t e = 0; e < states.size(); ++e) k[states[e].texel] = std::max(k[states[e].texel], resumed[e]);
        cone_steps_of_texels(field, pyramid, kind, options, seeds, again, k);
        resumed_count += states.size();
        restarted_count += again.size();
        cpu_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - cpu_start).count();
        first += count;
        if (options.progress)
            options.progress(kConeSeedProgress + (1.0 - kConeSeedProgress) * double(first) / double(n));
        // The next one: to take kChunkSeconds at this one's pace, growing at most fourfold, and,
        // where searches ran out of nodes, to about three quarters of the searches b_resume holds
        // at this one's rate (a ramp's second dispatch had four times the first one's texels and
        // more searches to save than room).
        std::size_t most = kMaxChunkTexels;
        if (saved > 0) most = std::min(most, std::size_t(0.75 * double(capacity) * double(count) / double(saved)));
        chunk = next_chunk(count, seconds, most, unit);
    }
    if (report) {
        report->search_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - search_start).count();
        report->cpu_ms = cpu_seconds * 1000.0;
        report->resumed = resumed_count;
        report->restarted = restarted_count;
        report->seed_ms = seed_ms;
        report->seeds_on_cpu = cpu_seeds;
    }
    if (const GLenum e = glGetError(); e != GL_NO_ERROR)
        throw Error(subject, "OpenGL error " + std::to_string(e) + " while building the cone map on the GPU");

    ConeMap map;
    map.width = field.width;
    map.height = field.height;
    map.kind = kind;
    map.heights = field.texels;
    map.ratios.resize(n);
    const std::vector<float>& ratio_of = cone_ratio_table(options.format);
    const std::uint32_t max_steps = std::uint32_t(ratio_of.size() - 1);
    for (std::size_t i = 0; i < n; ++i) map.ratios[i] = ratio_of[std::min(k[i], max_steps)];
    return map;
}

} // namespace pr
