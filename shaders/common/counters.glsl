// Instrumented variants (PR_COUNT_SAMPLES, used by bench): per-draw totals and a histogram of
// height samples per fragment, for fragments that ran the technique to the end (shown or
// discarded: a discarded fragment's samples cost as much). Call count_fragment() once per
// fragment, after the last height sample. The total is summed from the histogram on the CPU, in
// 64 bits (a 32-bit total wrapped past 4.3 G samples: a 4K frame at --steps 1024), with the
// samples of the fragments in its last bin (that many or more) summed here apart, in two words
// (thirty-second session: one word wrapped past 4.3 G samples in that bin). The prism walk
// counts the prisms its view ray crosses (count_prism(), once per prism), totalled in 64 bits
// from two words, and the most one fragment's ray crossed.
#ifdef PR_COUNT_SAMPLES
layout(std430, binding = PR_SSBO_COUNTERS) buffer Counters {
    uint c_fragments;
    uint c_overflow_low; // the last bin's samples, in two words (one wrapped past 4.3 G samples)
    uint c_prisms_low;
    uint c_prisms_high;
    uint c_prisms_most;
    uint c_overflow_high;
    uint c_histogram[];
};
#endif

int g_walk_prisms = 0;

void count_prism()
{
#ifdef PR_COUNT_SAMPLES
    ++g_walk_prisms;
#endif
}

void count_fragment()
{
#ifdef PR_COUNT_SAMPLES
    int last = int(c_histogram.length()) - 1;
    atomicAdd(c_fragments, 1u);
    if (g_height_samples >= last) {
        uint before = atomicAdd(c_overflow_low, uint(g_height_samples));
        if (before + uint(g_height_samples) < before) atomicAdd(c_overflow_high, 1u); // the low word wrapped
    }
    atomicAdd(c_histogram[min(g_height_samples, last)], 1u);
    if (g_walk_prisms > 0) {
        atomicMax(c_prisms_most, uint(g_walk_prisms));
        uint before = atomicAdd(c_prisms_low, uint(g_walk_prisms));
        if (before + uint(g_walk_prisms) < before) atomicAdd(c_prisms_high, 1u); // the low word wrapped
    }
#endif
}
