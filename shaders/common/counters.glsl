// Instrumented variants (PR_COUNT_SAMPLES, used by bench): per-draw totals and a histogram of
// height samples per fragment, for fragments that ran the technique to the end (shown or
// discarded: a discarded fragment's samples cost as much). Call count_fragment() once per
// fragment, after the last height sample. The total is summed from the histogram on the CPU, in
// 64 bits (a 32-bit total wrapped past 4.3 G samples: a 4K frame at --steps 1024), with the
// samples of the fragments past its exact bins (8192 or more) summed here apart, in two words
// (thirty-second session: one word wrapped past 4.3 G samples in that bin). The prism walk
// counts the prisms its view ray crosses (count_prism(), once per prism), totalled in 64 bits
// from two words, and the most one fragment's ray crossed. The fragments and each bin are two
// words too (thirty-fourth session: one wrapped past 4.3 G fragments, 1100 layers over 2048²,
// and bench reported 318,767,104; found by a review): the high word takes the low one's carry.
#ifdef PR_COUNT_SAMPLES
layout(std430, binding = PR_SSBO_COUNTERS) buffer Counters {
    uint c_fragments_low;
    uint c_overflow_low; // samples of fragments past the exact bins, in two words (one wrapped past 4.3 G)
    uint c_prisms_low;
    uint c_prisms_high;
    uint c_prisms_most;
    uint c_overflow_high;
    uint c_fragments_high;
    uint c_histogram[]; // bin k's count in words 2k (low) and 2k + 1 (high)
};

// The bin of a fragment that took `n` samples: n itself below 8192 (exact), above it 1024 bins an
// octave, each 1/1024 to 1/2048 of its value wide, up to 2^31 (thirty-fifth session: 8,192
// bins, the last "that many or more", and a p95 past it read 8191 where every fragment took
// 22,530; found by an exploratory session). Renderer's sample_bin_low() gives a bin's lowest n.
const int kExactSampleBins = 1 << PR_EXACT_SAMPLE_BITS; // 8192

int sample_bin(int n)
{
    if (n < kExactSampleBins) return max(n, 0);
    int e = findMSB(n); // 13 .. 30
    return kExactSampleBins + ((e - PR_EXACT_SAMPLE_BITS) << PR_OCTAVE_SAMPLE_BITS) +
           ((n >> (e - PR_OCTAVE_SAMPLE_BITS)) & ((1 << PR_OCTAVE_SAMPLE_BITS) - 1));
}

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
    if (atomicAdd(c_fragments_low, 1u) == 0xffffffffu) atomicAdd(c_fragments_high, 1u);
    if (g_height_samples >= kExactSampleBins) { // (the bins past the exact ones: their samples summed here)
        uint before = atomicAdd(c_overflow_low, uint(g_height_samples));
        if (before + uint(g_height_samples) < before) atomicAdd(c_overflow_high, 1u); // the low word wrapped
    }
    count_in_bin(sample_bin(g_height_samples));
    if (g_walk_prisms > 0) {
        atomicMax(c_prisms_most, uint(g_walk_prisms));
        uint before = atomicAdd(c_prisms_low, uint(g_walk_prisms));
        if (before + uint(g_walk_prisms) < before) atomicAdd(c_prisms_high, 1u); // the low word wrapped
    }
#endif
}
