//! The machine a measurement ran on, in one line (for the benchmark and every report's header).

/// One line describing the machine: CPU model, logical cores, memory, OS.
pub fn machine() -> String {
    let cpu = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|s| s.trim().to_string())
        })
        .unwrap_or_else(|| "unknown CPU".to_string());
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let mem = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|s| s.lines().next().and_then(|l| l.split_whitespace().nth(1)).and_then(|k| k.parse::<f64>().ok()))
        .map_or_else(|| "unknown memory".to_string(), |kb| format!("{:.1} GiB", kb / 1024.0 / 1024.0));
    format!("{cpu}, {cores} logical cores, {mem}, {} {}", std::env::consts::OS, std::env::consts::ARCH)
}
