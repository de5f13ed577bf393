//! The quantities the explorer colours the mesh by: volume fields (von Mises stress, velocity
//! magnitude) and contact-interface fields (pressure, slip, gap; METHOD §5), with their display
//! units.

/// What the mesh is coloured by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Quantity {
    /// Von Mises stress averaged to nodes.
    VonMises,
    /// Velocity magnitude.
    Velocity,
    /// Contact pressure on contact interfaces.
    Pressure,
    /// Accumulated slip on contact interfaces.
    Slip,
    /// Gap on contact interfaces.
    Gap,
}

impl Quantity {
    /// Every quantity, in menu order.
    pub const ALL: [Quantity; 5] = [
        Quantity::VonMises,
        Quantity::Velocity,
        Quantity::Pressure,
        Quantity::Slip,
        Quantity::Gap,
    ];

    /// Menu label.
    pub fn label(self) -> &'static str {
        match self {
            Quantity::VonMises => "von Mises stress",
            Quantity::Velocity => "velocity magnitude",
            Quantity::Pressure => "contact pressure",
            Quantity::Slip => "slip",
            Quantity::Gap => "gap",
        }
    }

    /// Display unit.
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::VonMises | Quantity::Pressure => "MPa",
            Quantity::Velocity => "m/s",
            Quantity::Slip | Quantity::Gap => "µm",
        }
    }

    /// Factor from SI to the display unit.
    pub fn scale(self) -> f64 {
        match self {
            Quantity::VonMises | Quantity::Pressure => 1e-6,
            Quantity::Velocity => 1.0,
            Quantity::Slip | Quantity::Gap => 1e6,
        }
    }

    /// Whether it lives on contact interfaces (the bodies are drawn grey around it).
    pub fn on_interfaces(self) -> bool {
        matches!(self, Quantity::Pressure | Quantity::Slip | Quantity::Gap)
    }
}
