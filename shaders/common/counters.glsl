// Instrumented variants (PR_COUNT_SAMPLES, used by bench): per-draw totals and a histogram of
// height samples per fragment, for fragments that ran the technique to the end (shown or
// discarded: a discarded fragment's samples cost as much). Call count_fragment() once per
// fragment, after the last height sample. The total is summed from the histogram on the CPU, in
// 64 bits (a 32-bit total wrapped past 4.3 G samples: a 4K frame at --steps 1024), with the
// samples of the fragments in its last bin (that many or more) summed here apart.
#ifdef PR_COUNT_SAMPLES
layout(std430, binding = PR_SSBO_COUNTERS) buffer Counters {
    uint c_fragments;
    uint c_overflow_samples;
    uint c_histogram[];
};
#endif

void count_fragment()
{
#ifdef PR_COUNT_SAMPLES
    int last = int(c_histogram.length()) - 1;
    atomicAdd(c_fragments, 1u);
    if (g_height_samples >= last) atomicAdd(c_overflow_samples, uint(g_height_samples));
    atomicAdd(c_histogram[min(g_height_samples, last)], 1u);
#endif
}
