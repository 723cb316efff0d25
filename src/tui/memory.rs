//! Big blocks given back to the system when they are freed.
//!
//! glibc's allocator maps a block of its own only when it is larger than a threshold, and
//! raises that threshold to the size of every mapped block freed (up to 32 MiB). Binding a
//! big mesh frees many blocks of a few megabytes; the blocks after them come from the heap,
//! which gives memory back only from its top, so the process keeps what the bind freed
//! and the levels of detail then grow it further: the editor on a 431k-vertex head peaked
//! at about 460 MB while it used about 290 (BENCHMARKS.md, big heads). A fixed threshold of
//! 1 MiB keeps every block that size or larger mapped on its own, unmapped when freed;
//! smaller ones (a frame's buffers, kept between frames anyway) come from the heap as
//! before.

/// The size from which a block is mapped on its own (and unmapped when freed).
pub const MAPPED_FROM: usize = 1 << 20;

/// Makes the allocator give blocks of [`MAPPED_FROM`] bytes or more back to the system
/// when they are freed, for the rest of the process (glibc on Linux; elsewhere nothing
/// changes). For commands that hold a big mesh: the editor, `render`.
pub fn give_back_big_blocks() {
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: mallopt only sets an allocator parameter; any value is accepted or refused
    // (returning 0), and blocks already handed out are not touched.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, MAPPED_FROM as libc::c_int);
    }
}

#[cfg(all(test, target_os = "linux", target_env = "gnu"))]
mod tests {
    /// The process's resident memory, in bytes.
    fn resident() -> usize {
        let status = std::fs::read_to_string("/proc/self/status").unwrap();
        let line = status.lines().find(|l| l.starts_with("VmRSS:")).unwrap();
        line.split_whitespace()
            .nth(1)
            .unwrap()
            .parse::<usize>()
            .unwrap()
            * 1024
    }

    /// A block of 8 MiB freed after another of that size was freed (which, left to itself,
    /// glibc takes as the sign to serve such blocks from its heap) leaves the process: its
    /// memory is no longer resident. Checked in a process of its own (this test binary
    /// again, running only this test): other tests leave free blocks in the heap that a
    /// new block would be served from.
    #[test]
    fn a_freed_big_block_leaves_the_process() {
        const CHILD: &str = "GRIMACE_TEST_FRESH_HEAP";
        if std::env::var_os(CHILD).is_some() {
            return freed_blocks_leave();
        }
        let name = "tui::memory::tests::a_freed_big_block_leaves_the_process";
        let out = std::process::Command::new(std::env::current_exe().unwrap())
            .args([name, "--exact", "--test-threads=1", "--nocapture"])
            .env(CHILD, "1")
            .output()
            .unwrap();
        let text = String::from_utf8_lossy(&out.stdout) + String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{text}");
        assert!(text.contains("1 passed"), "the check ran: {text}");
    }

    /// The check itself, in a fresh process.
    fn freed_blocks_leave() {
        super::give_back_big_blocks();
        const SIZE: usize = 8 << 20;
        let drops: Vec<isize> = (0..3)
            .map(|_| {
                drop(std::hint::black_box(vec![1u8; SIZE]));
                let block = std::hint::black_box(vec![1u8; SIZE]);
                let held = resident();
                drop(block);
                held as isize - resident() as isize
            })
            .collect();
        assert!(
            drops.iter().all(|&d| d >= (SIZE * 3 / 4) as isize),
            "resident memory after freeing 8 MiB: {drops:?} bytes less"
        );
    }
}
