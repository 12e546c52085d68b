// The cloth's material from a look (looks.json: `foldcast looks --json`): its warp and weft
// colours woven into a tile of its weave (plain, twill, satin, knit; none for a pile), the
// tile's relief as a bump map, and its roughness, specular and sheen: the appearance fields
// the path tracer reads (docs/looks.md), the tile repeating at the look's yarn spacing
// (repeat_mm) in the mesh's UVs, which are in metres (drape writes them so).
import * as THREE from 'three';

const kYarnPx = 16;  // texels across one yarn

// Which yarn is on top in cell (x, y) of the tile: true = warp (runs along v), false = weft.
function weavePattern(weave, twillFloat) {
  if (weave === 'plain') return { period: 2, warpUp: (x, y) => (x + y) % 2 === 0 };
  if (weave === 'twill') {
    const p = Math.max(2, twillFloat) + 1;
    return { period: p, warpUp: (x, y) => (((x - y) % p) + p) % p < p - 1 };
  }
  if (weave === 'satin') return { period: 5, warpUp: (x, y) => x !== (2 * y) % 5 };  // 5-harness, warp-faced
  return null;
}

function shade(hex, f) {
  return '#' + new THREE.Color(hex).multiplyScalar(f).getHexString();
}

// A yarn cell: the yarn's colour, lighter along its crest; its height the same profile.
function drawYarn(colour, height, x, y, size, alongV, fill) {
  for (const [ctx, centre, edge] of [[colour, fill, shade(fill, 0.72)], [height, '#ffffff', '#202020']]) {
    const g = alongV ? ctx.createLinearGradient(x, 0, x + size, 0) : ctx.createLinearGradient(0, y, 0, y + size);
    g.addColorStop(0, edge);
    g.addColorStop(0.5, centre);
    g.addColorStop(1, edge);
    ctx.fillStyle = g;
    ctx.fillRect(x, y, size, size);
  }
}

function drawKnit(colour, height, size, fill) {
  // One stitch per cell: two slanted legs meeting at the bottom (a jersey's V).
  for (const [ctx, stroke, back] of [[colour, fill, shade(fill, 0.6)], [height, '#ffffff', '#000000']]) {
    ctx.fillStyle = back;
    ctx.fillRect(0, 0, size, size);
    ctx.strokeStyle = stroke;
    ctx.lineWidth = size * 0.32;
    ctx.lineCap = 'round';
    ctx.beginPath();
    ctx.moveTo(size * 0.18, size * 0.05);
    ctx.lineTo(size * 0.5, size * 0.9);
    ctx.moveTo(size * 0.82, size * 0.05);
    ctx.lineTo(size * 0.5, size * 0.9);
    ctx.stroke();
  }
}

// { map, bumpMap, tileM } for a look's appearance, or null for a weave of none.
function weaveTextures(appearance, maxAnisotropy) {
  const warp = appearance.base_colour.srgb_hex;
  const weft = appearance.weft_colour?.srgb_hex ?? shade(warp, 0.88);
  const pattern = weavePattern(appearance.weave, appearance.twill_float);
  if (!pattern && appearance.weave !== 'knit') return null;
  const cells = pattern ? pattern.period : 1;
  const size = cells * kYarnPx * (pattern ? 1 : 2);
  const canvases = [document.createElement('canvas'), document.createElement('canvas')];
  for (const c of canvases) c.width = c.height = size;
  const [colour, height] = canvases.map((c) => c.getContext('2d'));
  if (pattern) {
    for (let y = 0; y < cells; ++y)
      for (let x = 0; x < cells; ++x) {
        const up = pattern.warpUp(x, y);
        drawYarn(colour, height, x * kYarnPx, y * kYarnPx, kYarnPx, up, up ? warp : weft);
      }
  } else {
    drawKnit(colour, height, size, warp);
  }
  const textures = canvases.map((c) => {
    const t = new THREE.CanvasTexture(c);
    t.wrapS = t.wrapT = THREE.RepeatWrapping;
    t.anisotropy = maxAnisotropy;
    return t;
  });
  textures[0].colorSpace = THREE.SRGBColorSpace;
  const yarnM = (appearance.repeat_mm || 1) / 1000;
  const tileM = yarnM * (pattern ? cells : 2);
  for (const t of textures) t.repeat.set(1 / tileM, 1 / tileM);
  return { map: textures[0], bumpMap: textures[1], tileM };
}

export function createClothMaterial() {
  return new THREE.MeshPhysicalMaterial({ color: 0xb8442e, roughness: 0.85, side: THREE.DoubleSide });
}

// Puts `look` (an entry of looks.json) on `material`; returns what it applied (for the tests).
export function applyLook(material, look, maxAnisotropy) {
  const a = look.appearance;
  material.map?.dispose();
  material.bumpMap?.dispose();
  const weave = weaveTextures(a, maxAnisotropy);
  material.map = weave?.map ?? null;
  material.bumpMap = weave?.bumpMap ?? null;
  material.bumpScale = (a.bump_strength ?? 1) * 1.5;
  // The weave texture carries the colour; without one the base colour does.
  material.color.set(weave ? '#ffffff' : a.base_colour.srgb_hex);
  material.roughness = a.roughness;
  // The looks' specular is the principled model's (0.5: F0 = 0.04, three's default).
  material.specularIntensity = Math.min(1, (a.specular ?? 0.5) / 0.5);
  material.sheen = 1;
  material.sheenColor.set(a.sheen_colour?.srgb_hex ?? '#000000');
  material.sheenRoughness = a.sheen_roughness ?? 0.5;
  material.needsUpdate = true;
  return { name: look.name, weave: a.weave, textured: Boolean(weave), tileMm: weave ? weave.tileM * 1000 : null,
    sheenColour: a.sheen_colour?.srgb_hex ?? null, roughness: a.roughness };
}
