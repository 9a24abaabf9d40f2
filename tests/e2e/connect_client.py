"""A minimal Connect-protocol client of koma_server's HTTP port for the e2e tests (stdlib
http.client, one keep-alive connection): a unary call with a binary body, its answer as a gRPC
status code and message, so the tests compare the HTTP path with the gRPC one directly."""
import http.client
import json

import grpc

CODES = {c.name.lower(): c for c in grpc.StatusCode}
CODES['canceled'] = grpc.StatusCode.CANCELLED  # Connect's spelling


class ConnectClient:
    def __init__(self, port, timeout_s=60):
        self.port = port
        self.timeout_s = timeout_s
        self.connection = None

    def call(self, rpc, request_bytes, timeout_ms=None):
        """POST /koma.v1.Retime/RPC as application/proto: (grpc.StatusCode, message, answer
        bytes, HTTP status). Reconnects once if the server closed the kept-alive connection."""
        headers = {'Content-Type': 'application/proto', 'Connect-Protocol-Version': '1'}
        if timeout_ms is not None:
            headers['Connect-Timeout-Ms'] = str(int(timeout_ms))
        for attempt in (0, 1):
            if self.connection is None:
                self.connection = http.client.HTTPConnection('127.0.0.1', self.port,
                                                             timeout=self.timeout_s)
            try:
                self.connection.request('POST', '/koma.v1.Retime/' + rpc, body=request_bytes,
                                        headers=headers)
                response = self.connection.getresponse()
                body = response.read()
                break
            except (ConnectionError, http.client.HTTPException):
                self.close()
                if attempt:
                    raise
        if response.getheader('Connection', '').lower() == 'close':
            self.close()
        if response.status == 200:
            return grpc.StatusCode.OK, '', body, 200
        error = json.loads(body)
        return CODES[error['code']], error['message'], b'', response.status

    def close(self):
        if self.connection is not None:
            self.connection.close()
            self.connection = None
