//! What every benchmark prints first (README "Benchmarks"): these machines differ and are
//! shared, so a figure means nothing without the CPU model, its cores, the load while it ran
//! and the lavapipe version that rendered.

use blockworld::render::Renderer;

/// The CPU model from `/proc/cpuinfo` (Linux), or `unknown`.
fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, v)| v.trim().to_string())
        })
        .unwrap_or_else(|| "unknown".into())
}

/// The 1, 5 and 15 minute load averages from `/proc/loadavg`, or `unknown`.
pub fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .map(|t| t.split_whitespace().take(3).collect::<Vec<_>>().join(" "))
        .unwrap_or_else(|_| "unknown".into())
}

/// The banner: CPU model, logical cores, load average, and the renderer's adapter (lavapipe's
/// LLVM version) when one is running.
pub fn banner(renderer: Option<&Renderer>) -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let mut s = format!(
        "machine: {} ({cores} cores), load average {} (1, 5, 15 min)\n",
        cpu_model(),
        load_average()
    );
    if let Some(r) = renderer {
        s.push_str(&format!("renderer: {}\n", r.adapter_info()));
    }
    s
}
