// Instrumented variants (PR_COUNT_SAMPLES, used by bench): per-draw totals and a histogram of
// height samples per fragment, for fragments that ran the technique to the end (shown or
// discarded: a discarded fragment's samples cost as much). Call count_fragment() once per
// fragment, after the last height sample.
#ifdef PR_COUNT_SAMPLES
layout(std430, binding = PR_SSBO_COUNTERS) buffer Counters {
    uint c_fragments;
    uint c_samples;
    uint c_histogram[];
};
#endif

void count_fragment()
{
#ifdef PR_COUNT_SAMPLES
    atomicAdd(c_fragments, 1u);
    atomicAdd(c_samples, uint(g_height_samples));
    atomicAdd(c_histogram[min(g_height_samples, int(c_histogram.length()) - 1)], 1u);
#endif
}
