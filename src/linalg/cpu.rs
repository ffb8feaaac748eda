//! The processor's vector instructions, as the float kernels choose their code by them.
//!
//! **Why not the standard library's detection alone.** `is_x86_feature_detected!` asks the
//! processor with `cpuid` the first time it is used, about ten queries; in a virtual machine
//! each one traps to the hypervisor. On the 2-core machine that first question cost 36–52 µs
//! (one `cpuid` 4.4–7.4 µs), a third of a 10-state `zoh`'s whole time above the process floor.
//! The C library made the same queries at start-up and keeps their answers: glibc (2.33 on)
//! exports them as `__x86_get_cpuid_feature_leaf`, the function `<sys/platform/x86.h>`'s
//! `CPU_FEATURE_PRESENT` reads. It is looked up by name (`dlsym`), so a C library without it
//! still runs the program, and the standard library's detection answers there.
//!
//! **Identity.** The rules are the standard library's: a feature the processor reports
//! (`cpuid` leaf 1's ECX, leaf 7's EBX, as glibc stored them) counts only when the operating
//! system saves the registers it uses — XMM and YMM state (`XCR0` bits 1–2) for AVX, AVX2 and
//! FMA, and the AVX-512 state too (bits 5–7) for AVX-512 — read with `xgetbv`, which does not
//! trap, and only where `OSXSAVE` says it may be executed. A test compares every answer with
//! `is_x86_feature_detected!` on the machine it runs on.
//!
//! **Cost.** One `dlsym` (a hash lookup over the loaded libraries), two calls and one `xgetbv`,
//! once per process ([`features`] keeps the answer).

use std::sync::OnceLock;

/// The instruction sets the float kernels use, each usable by this process.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct Features {
    /// AVX: four `f64` a vector.
    pub avx: bool,
    /// AVX2 and FMA, both.
    pub avx2_fma: bool,
    /// AVX-512 Foundation: eight `f64` a vector, fused multiply-add included.
    pub avx512f: bool,
}

/// The processor's features, found the first time they are asked for.
pub fn features() -> Features {
    static FOUND: OnceLock<Features> = OnceLock::new();
    *FOUND.get_or_init(detect)
}

fn detect() -> Features {
    #[cfg(all(target_arch = "x86_64", target_os = "linux", target_env = "gnu"))]
    if let Some(found) = glibc::features() {
        return found;
    }
    standard()
}

/// The standard library's answers (`cpuid` on the spot).
fn standard() -> Features {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        Features {
            avx: has!("avx"),
            avx2_fma: has!("avx2") && has!("fma"),
            avx512f: has!("avx512f"),
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    Features::default()
}

/// Feature bits as `cpuid` reports them, and `XCR0` (0 where `xgetbv` may not run), to
/// [`Features`] by the standard library's rules.
#[cfg_attr(
    not(all(target_arch = "x86_64", target_os = "linux", target_env = "gnu")),
    allow(dead_code)
)]
fn from_bits(leaf1_ecx: u32, leaf7_ebx: u32, xcr0: u64) -> Features {
    let bit = |word: u32, b: u32| word & (1 << b) != 0;
    // the operating system saves XMM and YMM (AVX), and the opmask and ZMM state (AVX-512)
    let os_avx = bit(leaf1_ecx, 26) && bit(leaf1_ecx, 27) && xcr0 & 0x6 == 0x6;
    let os_avx512 = os_avx && xcr0 & 0xe0 == 0xe0;
    Features {
        avx: os_avx && bit(leaf1_ecx, 28),
        avx2_fma: os_avx && bit(leaf7_ebx, 5) && bit(leaf1_ecx, 12),
        avx512f: os_avx512 && bit(leaf7_ebx, 16),
    }
}

#[cfg(all(target_arch = "x86_64", target_os = "linux", target_env = "gnu"))]
#[allow(unsafe_code)]
mod glibc {
    use super::{from_bits, Features};
    use std::ffi::{c_char, c_void};

    /// `struct cpuid_feature` of `<bits/platform/x86.h>`: the registers `cpuid` returned
    /// (EAX, EBX, ECX, EDX) and the ones glibc marked usable.
    #[repr(C)]
    struct CpuidFeature {
        cpuid: [u32; 4],
        active: [u32; 4],
    }

    type Leaf = unsafe extern "C" fn(u32) -> *const CpuidFeature;

    extern "C" {
        fn dlsym(handle: *mut c_void, symbol: *const c_char) -> *mut c_void;
    }

    /// `CPUID_INDEX_1` and `CPUID_INDEX_7` of `<bits/platform/x86.h>`.
    const INDEX_1: u32 = 0;
    const INDEX_7: u32 = 1;
    const EBX: usize = 1;
    const ECX: usize = 2;

    pub(super) fn features() -> Option<Features> {
        // SAFETY: RTLD_DEFAULT is the null handle in glibc; the name is NUL-terminated
        let found = unsafe {
            dlsym(
                std::ptr::null_mut(),
                c"__x86_get_cpuid_feature_leaf".as_ptr(),
            )
        };
        if found.is_null() {
            return None;
        }
        // SAFETY: the symbol is glibc's `const struct cpuid_feature
        // *__x86_get_cpuid_feature_leaf (unsigned int)` (glibc 2.33 on, where it was added)
        let leaf: Leaf = unsafe { std::mem::transmute::<*mut c_void, Leaf>(found) };
        // SAFETY: glibc returns a pointer to its static feature table, valid for the whole
        // process, for every index (a zeroed entry for one it does not know)
        let (leaf1, leaf7) = unsafe { (leaf(INDEX_1).as_ref()?, leaf(INDEX_7).as_ref()?) };
        let ecx = leaf1.cpuid[ECX];
        let osxsave = ecx & (1 << 27) != 0;
        // SAFETY: OSXSAVE says the operating system enabled XGETBV
        let xcr0 = if osxsave { unsafe { xcr0() } } else { 0 };
        Some(from_bits(ecx, leaf7.cpuid[EBX], xcr0))
    }

    #[target_feature(enable = "xsave")]
    unsafe fn xcr0() -> u64 {
        std::arch::x86_64::_xgetbv(0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_c_librarys_answers_are_the_standard_librarys() {
        assert_eq!(detect(), standard());
        assert_eq!(features(), standard());
    }

    #[test]
    fn a_register_state_the_system_does_not_save_disables_its_instructions() {
        let (xsave, osxsave, avx, fma) = (1 << 26, 1 << 27, 1 << 28, 1 << 12);
        let every = xsave | osxsave | avx | fma;
        let (avx2, avx512f) = (1 << 5, 1 << 16);
        let all = Features {
            avx: true,
            avx2_fma: true,
            avx512f: true,
        };
        assert_eq!(from_bits(every, avx2 | avx512f, 0xe7), all);
        // no ZMM state: AVX-512 off, the rest on
        let no_zmm = from_bits(every, avx2 | avx512f, 0x7);
        assert_eq!(
            (no_zmm.avx, no_zmm.avx2_fma, no_zmm.avx512f),
            (true, true, false)
        );
        // no YMM state, or XGETBV not enabled: nothing
        assert_eq!(from_bits(every, avx2 | avx512f, 0xe3), Features::default());
        assert_eq!(
            from_bits(every & !osxsave, avx2 | avx512f, 0xe7),
            Features::default()
        );
        // FMA without AVX2 is not the pair
        assert!(!from_bits(every, avx512f, 0xe7).avx2_fma);
    }
}
