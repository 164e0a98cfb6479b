//! What every layer uses: typed errors (`error`), progress and cancellation (`monitor`),
//! memory estimates against what the process may still allocate (`memory`), the thread pool
//! (`pool`) and `.npy` files (`npy`).

pub mod error;
pub mod memory;
pub mod monitor;
pub mod npy;
pub mod pool;
