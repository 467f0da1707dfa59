//! How a measure of a problem is named, written in the tables and scaled on the plot.

/// How a measure is written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Unit {
    /// A fraction written as a percentage.
    Percent,
    /// A signed fraction written as a signed percentage.
    SignedPercent,
    /// Metres written in millimetres.
    Millimetre,
    /// Newtons.
    Newton,
}

/// One measure of a problem.
#[derive(Clone, Copy, Debug)]
pub struct Column {
    /// Header.
    pub name: &'static str,
    /// Unit.
    pub unit: Unit,
}

impl Column {
    /// The value written in the column's unit.
    pub fn format(&self, v: f64) -> String {
        match self.unit {
            Unit::Percent => format!("{:.3} %", v * 100.0),
            Unit::SignedPercent => format!("{:+.3} %", v * 100.0),
            Unit::Millimetre => format!("{:.3}", v * 1e3),
            Unit::Newton => format!("{v:.3}"),
        }
    }

    /// The axis label of the plotted measure.
    pub fn axis(&self) -> String {
        match self.unit {
            Unit::Percent | Unit::SignedPercent => format!("{} (%)", self.name),
            Unit::Millimetre => format!("{} (mm)", self.name.trim_end_matches(", mm")),
            Unit::Newton => format!("{} (N)", self.name),
        }
    }

    /// The value on the plot's axis scale (% or mm or N).
    pub fn scaled(&self, v: f64) -> f64 {
        match self.unit {
            Unit::Percent | Unit::SignedPercent => v.abs() * 100.0,
            Unit::Millimetre => v * 1e3,
            Unit::Newton => v,
        }
    }
}
