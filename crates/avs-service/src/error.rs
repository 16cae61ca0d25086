//! Errors as the API returns them: `{"error": {"code", "message", "field"?}}` with an HTTP
//! status that says the same.

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use serde::Serialize;
use utoipa::ToSchema;

/// What went wrong, by kind; the kind sets the HTTP status and the `code` word.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, ToSchema)]
#[serde(rename_all = "snake_case")]
pub enum ErrorCode {
    /// The request is malformed (not JSON, a wrong type, an unknown key): 400.
    BadRequest,
    /// A file or value is well-formed but invalid (what `avs validate` refuses): 400.
    InvalidInput,
    /// No such session, goal or robot request: 404.
    NotFound,
    /// The request does not fit the state (a goal that already ended, a request already
    /// answered): 409.
    Conflict,
    /// The server holds `--max-sessions` sessions already: 429.
    TooManySessions,
    /// A bearer token is required and was missing or wrong: 401.
    Unauthorized,
    /// A fault of the server: 500.
    Internal,
}

impl ErrorCode {
    /// The HTTP status of the kind.
    pub fn status(self) -> StatusCode {
        match self {
            Self::BadRequest | Self::InvalidInput => StatusCode::BAD_REQUEST,
            Self::NotFound => StatusCode::NOT_FOUND,
            Self::Conflict => StatusCode::CONFLICT,
            Self::TooManySessions => StatusCode::TOO_MANY_REQUESTS,
            Self::Unauthorized => StatusCode::UNAUTHORIZED,
            Self::Internal => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }
}

/// The body of an error: `{"code", "message", "field"?}`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema)]
pub struct ErrorBody {
    /// The kind.
    pub code: ErrorCode,
    /// What went wrong and what is expected, for a person.
    pub message: String,
    /// The request field at fault (a JSON path such as `knowledge` or `result.grid.data[3]`),
    /// when one is.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub field: Option<String>,
}

/// An error response: `{"error": ErrorBody}`.
#[derive(Debug, Clone, PartialEq, Serialize, ToSchema, thiserror::Error)]
#[error("{}", error.message)]
pub struct ApiError {
    /// The error.
    pub error: ErrorBody,
}

impl ApiError {
    /// An error of kind `code`.
    pub fn new(code: ErrorCode, message: impl Into<String>) -> Self {
        Self {
            error: ErrorBody {
                code,
                message: message.into(),
                field: None,
            },
        }
    }

    /// The same error, naming the request field at fault.
    pub fn field(mut self, field: impl Into<String>) -> Self {
        self.error.field = Some(field.into());
        self
    }

    /// `not_found`: no such `what` (e.g. `session s4`).
    pub fn not_found(what: impl std::fmt::Display) -> Self {
        Self::new(ErrorCode::NotFound, format!("no {what}"))
    }

    /// `invalid_input` about `field`.
    pub fn invalid(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::new(ErrorCode::InvalidInput, message).field(field)
    }

    /// `bad_request` about `field`.
    pub fn bad_request(field: impl Into<String>, message: impl Into<String>) -> Self {
        Self::new(ErrorCode::BadRequest, message).field(field)
    }
}

impl IntoResponse for ApiError {
    fn into_response(self) -> Response {
        (self.error.code.status(), axum::Json(self)).into_response()
    }
}

/// The field a serde error is about: its path, and for a missing key the key itself (serde
/// reports that at the enclosing object).
fn field_of(path: &str, message: &str, root: &str) -> String {
    // An unknown key is in the path already; a missing one is not.
    let key = message
        .strip_prefix("missing field `")
        .and_then(|rest| rest.split('`').next());
    let base = if path == "." || path == "?" || path.is_empty() {
        root.to_string()
    } else if root.is_empty() {
        path.to_string()
    } else {
        format!("{root}.{path}")
    };
    match (key, base.is_empty()) {
        (Some(k), true) => k.to_string(),
        (Some(k), false) => format!("{base}.{k}"),
        (None, true) => "body".to_string(),
        (None, false) => base,
    }
}

/// A request body read as JSON of type `T`, with errors that name the field (by
/// `serde_path_to_error`) in the API's error shape.
pub fn parse_json<'a, T: serde::Deserialize<'a>>(body: &'a [u8]) -> Result<T, ApiError> {
    if body.iter().all(u8::is_ascii_whitespace) {
        return Err(ApiError::bad_request(
            "body",
            "the request body is empty; expected a JSON object",
        ));
    }
    let de = &mut serde_json::Deserializer::from_slice(body);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let syntax = matches!(
            inner.classify(),
            serde_json::error::Category::Syntax | serde_json::error::Category::Eof
        );
        let inner = inner.to_string();
        // A syntax error inside a value names that value's key (`1e999` for `start.x`); one
        // before any key (an unclosed brace, a bare array) is the body's.
        let named = path.starts_with(|c: char| c.is_ascii_alphabetic());
        let field = if syntax && !named {
            "body".to_string()
        } else {
            field_of(&path, &inner, "")
        };
        ApiError::bad_request(field, format!("invalid JSON: {inner}"))
    })
}

/// JSON text read as type `T`, with errors naming the field under `at` (a robot's answer,
/// e.g. `result.detections[0].pose.x`).
pub fn from_str<T: serde::de::DeserializeOwned>(at: &str, text: &str) -> Result<T, ApiError> {
    let de = &mut serde_json::Deserializer::from_str(text);
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner().to_string();
        let field = field_of(&path, &inner, at);
        ApiError::new(ErrorCode::BadRequest, format!("{field}: {inner}")).field(field)
    })
}
