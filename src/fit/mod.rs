//! Parameters of the friction law from laboratory data (`stickslip fit`):
//! the datasets ([`data`]), what the parameters predict for each
//! ([`model`]), and the weighted least squares with their covariance
//! ([`least_squares`]). The job that puts them together is
//! [`crate::jobs::fit`].

pub mod data;
pub mod least_squares;
pub mod model;
pub mod series;
