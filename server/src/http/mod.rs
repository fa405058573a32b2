//! The HTTP layer: the state handlers reach ([`state`]), the one error type ([`error`]), the
//! extractors ([`extract`]), the router with its middleware ([`router`]) and the OpenAPI
//! document ([`openapi`]). The handlers themselves are in `crate::api`; what they do, apart from
//! reading a request and writing a response, is in `crate::service`.

pub mod error;
pub mod extract;
pub mod openapi;
pub mod router;
pub mod state;

pub use error::{ApiError, ErrorBody};
pub use openapi::{openapi, openapi_json};
pub use router::{app, API_PREFIX, OPENAPI_PATH};
pub use state::AppState;
