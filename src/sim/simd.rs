//! What the CPU offers the crate's hand-vectorised loops, checked at run time.

/// Whether this CPU runs AVX instructions: the XPBD spring loops and the plume's pressure
/// loops then run their copies compiled for AVX (same operations, no fused multiply-add, so
/// the same bits). The standard library caches the answer.
#[cfg(target_arch = "x86_64")]
#[inline]
pub(crate) fn avx_available() -> bool {
    std::arch::is_x86_feature_detected!("avx")
}
