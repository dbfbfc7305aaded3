// Instrumented variants (PR_COUNT_SAMPLES, used by bench): per-draw totals and a histogram of
// height samples per fragment, for fragments that ran the technique to the end (shown or
// discarded: a discarded fragment's samples cost as much). Call count_fragment() once per
// fragment, after the last height sample. The total is summed from the histogram on the CPU, in
// 64 bits (a 32-bit total wrapped past 4.3 G samples: a 4K frame at --steps 1024), with the
// samples of the fragments in its last bin (that many or more) summed here apart, in two words
// (thirty-second session: one word wrapped past 4.3 G samples in that bin). The prism walk
// counts the prisms its view ray crosses (count_prism(), once per prism), totalled in 64 bits
// from two words, and the most one fragment's ray crossed. The fragments and each bin are two
// words too (thirty-fourth session: one wrapped past 4.3 G fragments, 1100 layers over 2048²,
// and bench reported 318,767,104; found by a review): the high word takes the low one's carry.
#ifdef PR_COUNT_SAMPLES
layout(std430, binding = PR_SSBO_COUNTERS) buffer Counters {
    uint c_fragments_low;
    uint c_overflow_low; // the last bin's samples, in two words (one wrapped past 4.3 G samples)
    uint c_prisms_low;
    uint c_prisms_high;
    uint c_prisms_most;
    uint c_overflow_high;
    uint c_fragments_high;
    uint c_histogram[]; // bin k's count in words 2k (low) and 2k + 1 (high)
};

// Adds one to bin `bin`'s count, carrying into its high word.
void count_in_bin(int bin)
{
    if (atomicAdd(c_histogram[2 * bin], 1u) == 0xffffffffu) atomicAdd(c_histogram[2 * bin + 1], 1u);
}
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
    int last = int(c_histogram.length()) / 2 - 1;
    if (atomicAdd(c_fragments_low, 1u) == 0xffffffffu) atomicAdd(c_fragments_high, 1u);
    if (g_height_samples >= last) {
        uint before = atomicAdd(c_overflow_low, uint(g_height_samples));
        if (before + uint(g_height_samples) < before) atomicAdd(c_overflow_high, 1u); // the low word wrapped
    }
    count_in_bin(min(g_height_samples, last));
    if (g_walk_prisms > 0) {
        atomicMax(c_prisms_most, uint(g_walk_prisms));
        uint before = atomicAdd(c_prisms_low, uint(g_walk_prisms));
        if (before + uint(g_walk_prisms) < before) atomicAdd(c_prisms_high, 1u); // the low word wrapped
    }
#endif
}
