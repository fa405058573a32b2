# syntax=docker/dockerfile:1
# The fivex service image: builds the `fivex` binary from this workspace, runs it on slim Debian.
# docker-compose.yml runs `fivex serve` from it with the database on the /data volume.

FROM rust:1-bookworm AS build
WORKDIR /src
COPY . .
RUN --mount=type=cache,target=/usr/local/cargo/registry \
    --mount=type=cache,target=/src/target \
    cargo build --release -p fivex-server --bin fivex \
 && cp target/release/fivex /usr/local/bin/fivex

FROM debian:bookworm-slim
# curl is only for the compose health check.
RUN apt-get update \
 && apt-get install -y --no-install-recommends curl ca-certificates \
 && rm -rf /var/lib/apt/lists/* \
 && useradd --system --uid 10001 --home-dir /data fivex \
 && mkdir -p /data && chown fivex /data
COPY --from=build /usr/local/bin/fivex /usr/local/bin/fivex
USER fivex
WORKDIR /data
VOLUME /data
EXPOSE 8080
ENV RUST_LOG=info
ENTRYPOINT ["/usr/local/bin/fivex"]
CMD ["serve", "--db", "/data/fivex.db", "--addr", "0.0.0.0:8080"]
