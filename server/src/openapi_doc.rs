//! What the OpenAPI document says about the answers no handler writes: the extractors'
//! rejections (400 a path or query value or JSON that does not parse, 413 a body over the
//! limit, 422 JSON of the wrong shape), the JSON-only check (415, `content_type.rs`) and the
//! websocket handshake (its headers, 400 without them, 429/503 beyond the caps, `listen.rs`).
//! Written once here, from what each operation declares, so that a handler added later is
//! documented as exactly as the others (schemathesis checks it: `scripts/schemathesis.sh`).
//! The 401 and 403 of the token and origin checks are documented by `auth.rs` and `origin.rs`.

use axum::http::Method;
use serde_json::Value;
use utoipa::openapi::path::{Operation, Parameter, ParameterBuilder, ParameterIn};
use utoipa::openapi::{ObjectBuilder, Required, Type};

use crate::http::openapi::{error_response, for_each_api_operation};

/// The modifier (`#[openapi(modifiers(…))]`).
pub struct RejectionDoc;

impl utoipa::Modify for RejectionDoc {
    fn modify(&self, openapi: &mut utoipa::openapi::OpenApi) {
        for_each_api_operation(openapi, |method, _, operation| {
            if operation.responses.responses.contains_key("101") {
                websocket(operation);
            }
            let body = operation.request_body.as_ref().map(|b| b.content.keys().cloned().collect::<Vec<_>>());
            let json_body = body.as_ref().is_some_and(|types| types.iter().any(|t| t == "application/json"));
            if typed_parameters(operation) || json_body {
                add(operation, 400, "Malformed: a path or query value of the wrong type, or JSON that does not parse");
            }
            if body.is_some() {
                add(operation, 413, "The body is larger than 8 MiB + 64 KiB");
            }
            if method != Method::GET {
                add(
                    operation,
                    415,
                    "A content type this endpoint does not take (JSON endpoints: application/json), or a body without one",
                );
            }
            if json_body {
                add(operation, 422, "JSON of the wrong shape: a missing or unknown field, a value out of range");
            }
        });
    }
}

/// Whether the operation has a query parameter, or a path parameter that is not any string.
fn typed_parameters(operation: &Operation) -> bool {
    operation.parameters.iter().flatten().any(|p| {
        let json = serde_json::to_value(p).unwrap_or(Value::Null);
        json["in"] == "query" || (json["in"] == "path" && json["schema"]["type"] != "string")
    })
}

/// Adds an error answer unless the handler documents that status itself (with its own words).
fn add(operation: &mut Operation, status: u16, description: &str) {
    if !operation.responses.responses.contains_key(&status.to_string()) {
        error_response(operation, status, description);
    }
}

/// A websocket route: the handshake's headers (RFC 6455; a request without them is no
/// upgrade, 400) and the caps' refusals.
fn websocket(operation: &mut Operation) {
    let header = |name: &str, schema: ObjectBuilder, description: &str| -> Parameter {
        ParameterBuilder::new()
            .name(name)
            .parameter_in(ParameterIn::Header)
            .required(Required::True)
            .description(Some(description))
            .schema(Some(schema.schema_type(Type::String)))
            .build()
    };
    let parameters = operation.parameters.get_or_insert_with(Vec::new);
    parameters.extend([
        header("Upgrade", ObjectBuilder::new().enum_values(Some(["websocket"])), "The websocket handshake"),
        header("Connection", ObjectBuilder::new().enum_values(Some(["Upgrade"])), "The websocket handshake"),
        header("Sec-WebSocket-Version", ObjectBuilder::new().enum_values(Some(["13"])), "The websocket handshake"),
        header(
            "Sec-WebSocket-Key",
            ObjectBuilder::new().pattern(Some("^[A-Za-z0-9+/]{21}[AQgw]==$")),
            "16 random bytes in base64 (RFC 6455)",
        ),
    ]);
    add(operation, 400, "Not a websocket handshake (a missing or wrong Upgrade, Connection or Sec-WebSocket-… header)");
    add(operation, 429, "This client has `--max-websockets-per-client` websockets open; `Retry-After: 5`");
    add(operation, 503, "The service has `--max-websockets` websockets open; `Retry-After: 5`");
}
