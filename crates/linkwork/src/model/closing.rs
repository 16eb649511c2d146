//! How a drawing that did not close was closed (`crate::compile::close_drawing` closes it):
//! what was kept, the pins that missed, the bodies moved.

/// What a drawing that does not close keeps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Keep {
    /// the pins given: the bodies are moved until every joint holds (least squares)
    Given,
    /// the drawing's points: each pin is where the drawing puts it
    Drawn,
}

impl Keep {
    pub fn name(self) -> &'static str {
        match self {
            Keep::Given => "given",
            Keep::Drawn => "drawn",
        }
    }
}

/// One pin that misses its drawn point.
#[derive(Debug, Clone, PartialEq)]
pub struct PinMiss {
    pub joint: String,
    /// the body whose pin it is
    pub body: String,
    /// "pin_a" or "pin_b"
    pub pin: &'static str,
    /// how far the pin, placed by the body's drawn pose, is from the drawn point (across
    /// the slide line for a prismatic joint), in the model's length unit
    pub miss: f64,
    /// the pin given and the drawing's, in the body's frame
    pub given: [f64; 2],
    pub drawn: [f64; 2],
}

/// How a drawing that did not close was closed.
#[derive(Debug, Clone, PartialEq)]
pub struct Closing {
    pub keep: Keep,
    pub misses: Vec<PinMiss>,
    /// keeping the pins: (body, how far its origin moved, how far it turned (rad)), for
    /// the bodies that moved; empty when keeping the drawing
    pub moved: Vec<(String, f64, f64)>,
}
