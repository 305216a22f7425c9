// SPDX-License-Identifier: MIT
// Serves the built site on 127.0.0.1 only, with the MIME types a module worker and WebAssembly
// need and cross-origin isolation (so the cancel flag can be a SharedArrayBuffer).
// usage: node web/serve.cjs SITE_DIR [--port N]   (N = 0 picks a free port; default 8080)
// Prints "serving http://127.0.0.1:PORT/" once listening.
'use strict';
const http = require('http');
const fs = require('fs');
const path = require('path');

const MIME = {
  '.html': 'text/html; charset=utf-8', '.js': 'text/javascript; charset=utf-8', '.mjs': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8', '.json': 'application/json', '.wasm': 'application/wasm', '.png': 'image/png',
  '.jpg': 'image/jpeg', '.jpeg': 'image/jpeg', '.svg': 'image/svg+xml', '.txt': 'text/plain; charset=utf-8',
};

function serve(root, port, onListening) {
  root = path.resolve(root);
  const server = http.createServer((req, res) => {
    const headers = {
      'Cross-Origin-Opener-Policy': 'same-origin', 'Cross-Origin-Embedder-Policy': 'require-corp',
      'Cross-Origin-Resource-Policy': 'same-origin', 'X-Content-Type-Options': 'nosniff', 'Cache-Control': 'no-cache',
    };
    let pathname;
    try { pathname = decodeURIComponent(new URL(req.url, 'http://127.0.0.1').pathname); } catch { pathname = null; }
    if (req.method !== 'GET' && req.method !== 'HEAD') { res.writeHead(405, headers); return res.end(); }
    const file = pathname && path.join(root, pathname.endsWith('/') ? pathname + 'index.html' : pathname);
    if (!file || (file !== root && !file.startsWith(root + path.sep))) { res.writeHead(403, headers); return res.end('forbidden\n'); }
    fs.stat(file, (err, stat) => {
      if (err || !stat.isFile()) { res.writeHead(404, { ...headers, 'Content-Type': 'text/plain' }); return res.end('not found\n'); }
      res.writeHead(200, { ...headers, 'Content-Type': MIME[path.extname(file).toLowerCase()] || 'application/octet-stream', 'Content-Length': stat.size });
      if (req.method === 'HEAD') return res.end();
      fs.createReadStream(file).pipe(res);
    });
  });
  server.listen(port, '127.0.0.1', () => onListening(server.address().port));
  return server;
}

if (require.main === module) {
  const args = process.argv.slice(2);
  const portAt = args.indexOf('--port');
  const port = portAt >= 0 ? Number(args[portAt + 1]) : 8080;
  const root = args.find((a, i) => !a.startsWith('--') && i !== portAt + 1);
  if (!root || !fs.existsSync(path.join(root, 'index.html')) || !Number.isInteger(port)) {
    console.error('usage: node web/serve.cjs SITE_DIR [--port N]   (SITE_DIR holds index.html, e.g. build/wasm/site)');
    process.exit(2);
  }
  serve(root, port, (p) => console.log(`serving http://127.0.0.1:${p}/`));
}

module.exports = { serve };
