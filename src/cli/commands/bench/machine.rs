//! What every benchmark prints first (docs/benchmarks.md "Benchmarks"): these machines differ and are
//! shared, so a figure means nothing without the CPU model, its cores, the load while it ran
//! and the lavapipe version that rendered.

use blockworld::render::{adapter_summary, Backend, Renderer};

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

/// The banner's first line: CPU model, logical cores and load average. `bench generate` prints
/// it alone at the start and names the adapters its workers rendered on beside its table.
pub fn machine_line() -> String {
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    format!(
        "machine: {} ({cores} cores), load average {} (1, 5, 15 min)\n",
        cpu_model(),
        load_average()
    )
}

/// The banner: CPU model, logical cores, load average, and the renderer's adapter (lavapipe's
/// LLVM and Mesa versions): the running renderer's, or for a bench that times no rendering the
/// adapter this machine offers (or why there is none), so every table names its rasterizer.
pub fn banner(renderer: Option<&Renderer>) -> String {
    let mut s = machine_line();
    match renderer {
        Some(r) => s.push_str(&format!("renderer: {}\n", r.adapter_info())),
        None => s.push_str(&format!(
            "renderer (not timed by this bench): {}\n",
            adapter_summary(Backend::Vulkan).unwrap_or_else(|e| e.to_string())
        )),
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bench that times no rendering still names the machine and its rasterizer (or why
    /// there is none): two lines, in that order.
    #[test]
    fn banner_without_a_renderer_names_the_machine_and_its_adapter() {
        let b = banner(None);
        let lines: Vec<&str> = b.lines().collect();
        assert_eq!(lines.len(), 2, "{b}");
        assert!(lines[0].starts_with("machine: ") && lines[0].contains(" cores), load average "));
        let adapter = lines[1].strip_prefix("renderer (not timed by this bench): ");
        assert!(adapter.is_some_and(|a| !a.is_empty()), "{b}");
    }
}
