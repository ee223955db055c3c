//! Binning: the frame data, and the binner that puts each primitive into the polygon list of
//! every tile it really covers.

pub mod binner;
pub mod frame_data;
pub mod grid;
