//! Streamed outcomes. A flow whose document may be larger than memory (the rows of `reference`,
//! up to 10⁷ per run; the events of `events`) hands it to a [`Sink`]: its head once, after the
//! request is checked and before any row is computed (a face sizes and opens its output
//! there), then every row in order. Memory stays that of one batch of rows whatever the length
//! of the run, and the document is the same for any number of threads.

use crate::FlowError;

/// Where a streamed flow puts its document: a head of type `H`, then rows of type `R`.
pub trait Sink<H, R> {
    /// What stops the flow: its own errors ([`FlowError`]) and the sink's (an output that cannot
    /// be written, an interrupt).
    type Error: From<FlowError>;
    /// The head of the document, before any row is computed.
    fn head(&mut self, head: &H) -> Result<(), Self::Error>;
    /// The next row.
    fn row(&mut self, row: R) -> Result<(), Self::Error>;
}

/// A sink that keeps the head and every row: the whole document in memory (the Python face,
/// tests).
#[derive(Clone, Debug)]
pub struct Collect<H, R> {
    pub head: Option<H>,
    pub rows: Vec<R>,
}

impl<H, R> Default for Collect<H, R> {
    fn default() -> Self {
        Self {
            head: None,
            rows: Vec::new(),
        }
    }
}

impl<H: Clone, R> Sink<H, R> for Collect<H, R> {
    type Error = FlowError;
    fn head(&mut self, head: &H) -> Result<(), FlowError> {
        self.head = Some(head.clone());
        Ok(())
    }
    fn row(&mut self, row: R) -> Result<(), FlowError> {
        self.rows.push(row);
        Ok(())
    }
}
