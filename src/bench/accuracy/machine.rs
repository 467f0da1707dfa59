//! The machine and the date a bench ran on, for the document (Linux: /proc; elsewhere what the
//! standard library tells).

use std::time::{SystemTime, UNIX_EPOCH};

/// Where and when.
#[derive(Clone, Debug)]
pub struct Machine {
    /// CPU model name ("unknown CPU" when not found).
    pub cpu: String,
    /// Logical cores.
    pub cores: usize,
    /// Physical memory, GiB (0 when not found).
    pub memory_gib: f64,
    /// Threads of the solver's pool.
    pub threads: usize,
    /// UTC date and time, `YYYY-MM-DD HH:MM UTC`.
    pub date: String,
    /// One-minute load average at the start (None when unknown): other work sharing the cores.
    pub load: Option<f64>,
}

impl Machine {
    /// This machine, now.
    pub fn now() -> Machine {
        let cpu = std::fs::read_to_string("/proc/cpuinfo")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("model name"))
                    .and_then(|l| l.split(':').nth(1))
                    .map(|m| m.trim().to_string())
            })
            .unwrap_or_else(|| "unknown CPU".into());
        let memory_gib = std::fs::read_to_string("/proc/meminfo")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("MemTotal:"))
                    .and_then(|l| l.split_whitespace().nth(1))
                    .and_then(|kb| kb.parse::<f64>().ok())
            })
            .map_or(0.0, |kb| kb / (1024.0 * 1024.0));
        let secs = SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_secs());
        Machine {
            cpu,
            cores: std::thread::available_parallelism().map_or(1, |n| n.get()),
            memory_gib,
            threads: rayon::current_num_threads(),
            date: utc_date(secs),
            load: std::fs::read_to_string("/proc/loadavg")
                .ok()
                .and_then(|s| s.split_whitespace().next()?.parse().ok()),
        }
    }

    /// One line: `2 cores (Intel Xeon …), 24 GiB, 2 solver threads, load 0.4; 2026-11-22 10:00
    /// UTC`.
    pub fn summary(&self) -> String {
        format!(
            "{} cores ({}), {:.0} GiB, {} solver threads{}; {}",
            self.cores,
            self.cpu,
            self.memory_gib,
            self.threads,
            self.load.map_or(String::new(), |l| format!(
                ", load average {l:.1} at the start"
            )),
            self.date
        )
    }
}

/// `YYYY-MM-DD HH:MM UTC` of a Unix time (days to civil date after H. Hinnant).
pub fn utc_date(secs: u64) -> String {
    let days = (secs / 86_400) as i64;
    let (hour, minute) = ((secs % 86_400) / 3600, (secs % 3600) / 60);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!("{year:04}-{month:02}-{day:02} {hour:02}:{minute:02} UTC")
}

#[cfg(test)]
mod tests {
    #[test]
    fn civil_dates() {
        assert_eq!(super::utc_date(0), "1970-01-01 00:00 UTC");
        // 2000-02-29 12:34 UTC (a leap day of a year divisible by 400).
        assert_eq!(super::utc_date(951_827_640), "2000-02-29 12:34 UTC");
        assert_eq!(super::utc_date(1_798_761_599), "2026-12-31 23:59 UTC");
    }
}
