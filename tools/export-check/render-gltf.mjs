#!/usr/bin/env node
// Renders a glTF 2.0 asset with three.js in headless Chromium on SwiftShader (WebGL 2 on the
// CPU), with the asset's own first camera node and its KHR_lights_punctual lights only, and
// clothbake's tone mapping, then writes the canvas pixels to a PNG.
//
//   node tools/export-check/render-gltf.mjs FILE OUT.png [--width W] [--height H] [--exposure E]
//
// Defaults: 512x512, exposure 1. Needs Debian's /usr/bin/chromium (or CHROMIUM=/path) and the
// packages of tools/export-check/package-lock.json (`npm ci` there). Nothing goes over the
// network: the page, three.js (from node_modules) and the asset are answered by Playwright's
// request interception on a made-up origin, every other request is aborted, and nothing
// listens on a port.
//
// Tone mapping, as clothbake's (see README.md): exposure E multiplies the linear radiance, then
// the ACES fit x(2.51x+0.03)/(x(2.43x+0.59)+0.14) clamped to [0,1], then the sRGB transfer
// function, which three applies itself for outputColorSpace = SRGBColorSpace.
//
// Prints the WebGL renderer string, the three.js revision, the camera and lights used and a
// summary of the pixels. Exit status: 0 written, 1 WebGL unavailable, the asset failed to load
// or render, or no camera; 2 unreadable input; 64 usage.
import { mkdtemp, readFile, rm, writeFile } from 'node:fs/promises';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import { deflateSync } from 'node:zlib';
import { chromium } from 'playwright-core';

const here = path.dirname(fileURLToPath(import.meta.url));
const threeRoot = path.join(here, 'node_modules', 'three');
const origin = 'http://export-check.localhost';

function usage(message) {
  if (message) console.error(`render-gltf: ${message}`);
  console.error('usage: render-gltf.mjs FILE OUT.png [--width W] [--height H] [--exposure E]');
  process.exit(64);
}

function parseArgs(argv) {
  const options = { width: 512, height: 512, exposure: 1 };
  const positional = [];
  for (let i = 0; i < argv.length; i++) {
    const arg = argv[i];
    const match = /^--(width|height|exposure)(?:=(.*))?$/.exec(arg);
    if (match) {
      const value = match[2] ?? argv[++i];
      if (value === undefined) usage(`${arg} needs a value`);
      const number = Number(value);
      if (match[1] === 'exposure') {
        if (!Number.isFinite(number) || number < 0) usage(`bad exposure ${value}`);
      } else if (!Number.isInteger(number) || number < 1 || number > 8192) {
        usage(`bad ${match[1]} ${value}`);
      }
      options[match[1]] = number;
    } else if (arg.startsWith('-')) {
      usage(`unknown option ${arg}`);
    } else {
      positional.push(arg);
    }
  }
  if (positional.length !== 2) usage();
  [options.file, options.out] = positional;
  return options;
}

// The page: three.js and GLTFLoader as ES modules through an import map, and one function that
// the script calls with the settings.
const page_html = `<!doctype html>
<html><head><meta charset="utf-8">
<style>html, body { margin: 0; background: #000; } canvas { display: block; }</style>
<script type="importmap">
{ "imports": { "three": "/three/build/three.module.js", "three/addons/": "/three/examples/jsm/" } }
</script>
<script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';

// clothbake's tone mapping (exposure, then the ACES fit clamped to [0, 1]); three applies the
// sRGB transfer function afterwards, as the output colour space is SRGBColorSpace.
const custom = 'vec3 CustomToneMapping( vec3 color ) { return color; }';
const chunk = THREE.ShaderChunk.tonemapping_pars_fragment;
if (!chunk.includes(custom)) throw new Error('three.js changed its CustomToneMapping stub');
THREE.ShaderChunk.tonemapping_pars_fragment = chunk.replace(custom, \`
vec3 CustomToneMapping( vec3 color ) {
	vec3 x = toneMappingExposure * color;
	return clamp( ( x * ( 2.51 * x + 0.03 ) ) / ( x * ( 2.43 * x + 0.59 ) + 0.14 ), 0.0, 1.0 );
}\`);

window.renderGltf = async ({ url, width, height, exposure }) => {
  const canvas = document.createElement('canvas');
  canvas.width = width;
  canvas.height = height;
  document.body.appendChild(canvas);
  const gl = canvas.getContext('webgl2', {
    antialias: false, alpha: false, depth: true, stencil: false, premultipliedAlpha: false,
    preserveDrawingBuffer: true, powerPreference: 'default', failIfMajorPerformanceCaveat: false,
  });
  if (!gl) throw new Error('WebGL 2 is unavailable in this browser (no context from getContext("webgl2"))');
  const debug = gl.getExtension('WEBGL_debug_renderer_info');
  const rendererString = gl.getParameter(debug ? debug.UNMASKED_RENDERER_WEBGL : gl.RENDERER);
  const vendorString = gl.getParameter(debug ? debug.UNMASKED_VENDOR_WEBGL : gl.VENDOR);

  const renderer = new THREE.WebGLRenderer({ canvas, context: gl, antialias: false });
  renderer.setPixelRatio(1);
  renderer.setSize(width, height, false);
  renderer.outputColorSpace = THREE.SRGBColorSpace;
  renderer.toneMapping = THREE.CustomToneMapping;
  renderer.toneMappingExposure = exposure;
  renderer.setClearColor(0x000000, 1);

  const gltf = await new GLTFLoader().loadAsync(url);
  const scene = gltf.scene;
  scene.background = null;
  scene.environment = null;
  scene.updateMatrixWorld(true);

  // The first node, in the order of glTF's nodes array, that holds a camera.
  const json = gltf.parser.json;
  const cameraNode = (json.nodes ?? []).findIndex((node) => node.camera !== undefined);
  if (cameraNode < 0) throw new Error('the glTF has no camera node');
  let camera = null;
  (await gltf.parser.getDependency('node', cameraNode)).traverse((o) => { if (!camera && o.isCamera) camera = o; });
  if (!camera) throw new Error('three did not make a camera of node ' + cameraNode);
  camera.updateWorldMatrix(true, false);
  if (camera.isPerspectiveCamera) {
    camera.aspect = width / height;
    camera.updateProjectionMatrix();
  }

  // Only the asset's own lights: GLTFLoader makes them from KHR_lights_punctual, and nothing
  // else lights the scene (no environment, no ambient light).
  const lights = [];
  scene.traverse((o) => {
    if (o.isLight) lights.push(o.type + ' "' + o.name + '" intensity ' + o.intensity + ' color ' + o.color.getHexString());
  });
  const materials = new Set();
  scene.traverse((o) => { if (o.isMesh) materials.add(o.material.type + ' "' + o.material.name + '"'); });

  renderer.render(scene, camera);
  const error = gl.getError();
  const pixels = new Uint8Array(width * height * 4);
  gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
  let binary = '';
  for (let i = 0; i < pixels.length; i += 0x8000) binary += String.fromCharCode.apply(null, pixels.subarray(i, i + 0x8000));
  return {
    rendererString, vendorString, revision: THREE.REVISION, glError: error,
    camera: camera.type + ' "' + camera.name + '" (node ' + cameraNode + ')', lights, materials: [...materials],
    pixels: btoa(binary),
  };
};
window.pageReady = true;
</script></head><body></body></html>`;

// A PNG (RGB, 8 bits) of the RGBA rows that readPixels gave, bottom row first.
function encodePng(rgba, width, height) {
  const rows = Buffer.alloc((width * 3 + 1) * height);
  for (let y = 0; y < height; y++) {
    const src = (height - 1 - y) * width * 4;
    let dst = y * (width * 3 + 1) + 1; // filter byte 0 before each row
    for (let x = 0; x < width; x++, dst += 3) {
      rows[dst] = rgba[src + x * 4];
      rows[dst + 1] = rgba[src + x * 4 + 1];
      rows[dst + 2] = rgba[src + x * 4 + 2];
    }
  }
  const crcTable = Array.from({ length: 256 }, (_, n) => {
    let c = n;
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    return c >>> 0;
  });
  const crc = (bytes) => {
    let c = 0xffffffff;
    for (const b of bytes) c = crcTable[(c ^ b) & 0xff] ^ (c >>> 8);
    return (c ^ 0xffffffff) >>> 0;
  };
  const chunk = (type, data) => {
    const out = Buffer.alloc(12 + data.length);
    out.writeUInt32BE(data.length, 0);
    out.write(type, 4, 'ascii');
    data.copy(out, 8);
    out.writeUInt32BE(crc(out.subarray(4, 8 + data.length)), 8 + data.length);
    return out;
  };
  const header = Buffer.alloc(13);
  header.writeUInt32BE(width, 0);
  header.writeUInt32BE(height, 4);
  header.set([8, 2, 0, 0, 0], 8); // 8 bits, truecolour, deflate, no filter, no interlace
  return Buffer.concat([
    Buffer.from([0x89, 0x50, 0x4e, 0x47, 0x0d, 0x0a, 0x1a, 0x0a]),
    chunk('IHDR', header),
    chunk('IDAT', deflateSync(rows, { level: 6 })),
    chunk('IEND', Buffer.alloc(0)),
  ]);
}

const contentTypes = {
  '.js': 'text/javascript', '.mjs': 'text/javascript', '.html': 'text/html',
  '.gltf': 'model/gltf+json', '.glb': 'model/gltf-binary', '.bin': 'application/octet-stream',
  '.png': 'image/png', '.jpg': 'image/jpeg', '.jpeg': 'image/jpeg', '.ktx2': 'image/ktx2',
  '.webp': 'image/webp',
};

async function main() {
  const options = parseArgs(process.argv.slice(2));
  const started = performance.now();
  const file = path.resolve(options.file);
  let asset;
  try {
    asset = await readFile(file);
  } catch (error) {
    console.error(`render-gltf: cannot read ${options.file}: ${error.message}`);
    return 2;
  }
  const assetDir = path.dirname(file);
  const assetName = path.basename(file);

  const executablePath = process.env.CHROMIUM || '/usr/bin/chromium';
  const userDataDir = await mkdtemp(path.join(tmpdir(), 'export-check-chromium-'));
  let context;
  try {
    try {
      // launchPersistentContext takes the fresh profile folder (Playwright refuses
      // --user-data-dir among args); it is removed at the end.
      context = await chromium.launchPersistentContext(userDataDir, {
        executablePath,
        headless: true,
        viewport: { width: options.width, height: options.height },
        deviceScaleFactor: 1,
        offline: false,
        args: [
          '--use-angle=swiftshader',
          '--enable-unsafe-swiftshader',
          '--ignore-gpu-blocklist',
          '--no-sandbox',
          '--disable-background-networking',
          '--disable-component-update',
          '--disable-sync',
          '--disable-quic',
          // No name is resolved: Chromium would otherwise look up Google's hosts (accounts,
          // clients2) in the background. The page's own origin needs no lookup, as every
          // request to it is answered by the route below.
          '--host-resolver-rules=MAP * ~NOTFOUND',
          '--no-first-run',
          '--no-default-browser-check',
          '--disable-extensions',
          '--disable-features=Translate,OptimizationHints,MediaRouter,DialMediaRouteProvider',
        ],
        timeout: 60_000,
      });
    } catch (error) {
      console.error(`render-gltf: cannot start ${executablePath}: ${error.message.split('\n')[0]}`);
      return 1;
    }
    const launched = performance.now();

    // Everything the page asks for is answered here; anything off the made-up origin is
    // aborted, so no request leaves the machine.
    await context.route('**/*', async (route) => {
      const url = new URL(route.request().url());
      if (url.origin !== origin) return route.abort('blockedbyclient');
      const name = decodeURIComponent(url.pathname);
      let body;
      let where;
      if (name === '/') {
        return route.fulfill({ status: 200, contentType: 'text/html', body: page_html });
      } else if (name.startsWith('/three/')) {
        where = path.join(threeRoot, path.normalize(name.slice('/three/'.length)));
        if (!where.startsWith(threeRoot + path.sep)) return route.fulfill({ status: 403 });
      } else if (name === `/asset/${assetName}`) {
        body = asset;
      } else if (name.startsWith('/asset/')) {
        where = path.resolve(assetDir, name.slice('/asset/'.length)); // external resources
      } else {
        return route.fulfill({ status: 404 });
      }
      try {
        body ??= await readFile(where);
      } catch {
        return route.fulfill({ status: 404, body: `not found: ${name}` });
      }
      const type = contentTypes[path.extname(name).toLowerCase()] ?? 'application/octet-stream';
      return route.fulfill({ status: 200, contentType: type, body });
    });

    const page = await context.newPage();
    page.setDefaultTimeout(300_000);
    const pageErrors = [];
    page.on('pageerror', (error) => pageErrors.push(error.message));
    page.on('console', (message) => {
      // (ANGLE's performance notes, such as the stall that readPixels causes, are noise.)
      if ((message.type() === 'error' || message.type() === 'warning') &&
          !/GL Driver Message \(OpenGL, Performance/.test(message.text())) {
        console.error(`render-gltf: page ${message.type()}: ${message.text()}`);
      }
    });
    await page.goto(`${origin}/`);
    try {
      await page.waitForFunction(() => window.pageReady === true, null, { timeout: 60_000 });
    } catch {
      console.error(`render-gltf: the page did not load three.js: ${pageErrors.join('; ') || 'timed out'}`);
      return 1;
    }

    let result;
    try {
      result = await page.evaluate((settings) => window.renderGltf(settings), {
        url: `${origin}/asset/${encodeURIComponent(assetName)}`,
        width: options.width,
        height: options.height,
        exposure: options.exposure,
      });
    } catch (error) {
      const message = error.message.replace(/^page\.evaluate: (Error: )?/, '').split('\n')[0]
        .replace(/[\x00-\x1f\x7f]/g, '?');
      console.error(`render-gltf: rendering ${options.file} failed: ${message}`);
      return 1;
    }
    const rendered = performance.now();

    console.log(`WebGL renderer: ${result.rendererString} (vendor ${result.vendorString})`);
    console.log(`three.js r${result.revision}, Chromium ${context.browser()?.version() ?? '?'}`);
    console.log(`camera: ${result.camera}, aspect ${options.width}/${options.height}`);
    console.log(`lights: ${result.lights.length ? result.lights.join('; ') : 'none (the image is black)'}`);
    console.log(`materials: ${result.materials.join('; ') || 'none'}`);
    if (result.glError !== 0) console.error(`render-gltf: WebGL error 0x${result.glError.toString(16)}`);

    const rgba = Buffer.from(result.pixels, 'base64');
    let lit = 0;
    let maximum = 0;
    let sum = 0;
    for (let i = 0; i < rgba.length; i += 4) {
      const m = Math.max(rgba[i], rgba[i + 1], rgba[i + 2]);
      if (m > 0) lit++;
      maximum = Math.max(maximum, m);
      sum += rgba[i] + rgba[i + 1] + rgba[i + 2];
    }
    const count = options.width * options.height;
    await writeFile(options.out, encodePng(rgba, options.width, options.height));
    console.log(
      `wrote ${options.out}: ${options.width}x${options.height}, exposure ${options.exposure}, ` +
        `${((100 * lit) / count).toFixed(1)}% of pixels non-black, max ${maximum}, ` +
        `mean ${(sum / (3 * count)).toFixed(2)}`,
    );
    console.log(
      `time: browser start ${((launched - started) / 1000).toFixed(2)} s, ` +
        `load and render ${((rendered - launched) / 1000).toFixed(2)} s`,
    );
    return result.glError === 0 ? 0 : 1;
  } finally {
    await context?.close().catch(() => {});
    await rm(userDataDir, { recursive: true, force: true }).catch(() => {});
  }
}

process.exitCode = await main();
