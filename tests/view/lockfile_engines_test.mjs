// The page is built with the Node.js and npm of the README's quick start: Debian 12's
// `nodejs` (18.20.4) and `npm` (9.2.0). Checks that web/package-lock.json can be installed
// by that npm (lockfile version) and that every package it pins admits that Node and npm
// in its `engines`; a newer esbuild or playwright-core that drops Node 18 fails here, at
// the lockfile, instead of in `npm ci` on a Debian machine.
//
// node lockfile_engines_test.mjs WEB_DIR
import fs from 'node:fs';
import path from 'node:path';

const DEBIAN_12 = { node: '18.20.4', npm: '9.2.0' };  // bookworm's nodejs 18.20.4+dfsg-1~deb12u3, npm 9.2.0~ds1-1
const NEWEST_LOCKFILE_NPM_9_READS = 3;

/// [major, minor, patch] of "1.2.3" or a partial "1.2" / "1" / "1.x" (missing parts: 0).
function parseVersion(text) {
  const match = /^v?(\d+)(?:\.(\d+|x|\*))?(?:\.(\d+|x|\*))?$/.exec(text);
  if (!match) throw new Error(`cannot read the version "${text}"`);
  return [1, 2, 3].map((i) => (match[i] === undefined || !/^\d+$/.test(match[i]) ? 0 : Number(match[i])));
}

function compare(a, b) {
  for (let i = 0; i < 3; ++i) if (a[i] !== b[i]) return a[i] < b[i] ? -1 : 1;
  return 0;
}

/// Whether @a version meets one comparator: >=, >, <=, <, =, ^, ~ or a bare (partial) version.
function meets(version, comparator) {
  const [, operator, operand] = /^(>=|<=|>|<|=|\^|~)?\s*(.+)$/.exec(comparator);
  const bound = parseVersion(operand);
  const order = compare(version, bound);
  const parts = operand.split('.').filter((part) => /^\d+$/.test(part)).length;
  switch (operator) {
    case '>=': return order >= 0;
    case '>': return order > 0;
    case '<=': return order <= 0;
    case '<': return order < 0;
    case '^': {
      const kept = bound.findIndex((part) => part !== 0);  // ^0.2.3 keeps 0.2, ^1.2 keeps 1
      const fixed = kept < 0 ? Math.max(parts, 1) : Math.min(kept + 1, Math.max(parts, 1));
      return order >= 0 && version.slice(0, fixed).every((part, i) => part === bound[i]);
    }
    case '~': return order >= 0 && version.slice(0, Math.min(Math.max(parts, 1), 2)).every((part, i) => part === bound[i]);
    default: return version.slice(0, Math.max(parts, 1)).every((part, i) => part === bound[i]);  // = or bare: x-range
  }
}

/// Whether @a version is in the npm range @a range ("a b || c": all of a and b, or c).
function admits(range, version) {
  const parsed = parseVersion(version);
  return range.split('||').some((alternative) => {
    const comparators = alternative.trim().replace(/(>=|<=|>|<|=|\^|~)\s+/g, '$1').split(/\s+/).filter(Boolean);
    if (comparators.includes('-')) throw new Error(`hyphen ranges are not read here: "${range}"`);
    return comparators.length === 0 || comparators.includes('*') || comparators.every((c) => meets(parsed, c));
  });
}

/// The range reader's own checks: each must hold, or the test below proves nothing.
function checkTheReader() {
  const cases = [
    ['>=18', true], ['>=14.19.0', true], ['>=20', false], ['>18.20.4', false], ['^18.12.0', true],
    ['^20.0.0', false], ['^16 || ^18 || >=20', true], ['>=16 <18', false], ['~18.20.0', true],
    ['~18.19.0', false], ['18.x', true], ['18', true], ['*', true], ['>= 18.17', true], ['<18.20.5', true],
  ];
  return cases.filter(([range, expected]) => admits(range, DEBIAN_12.node) !== expected)
    .map(([range, expected]) => `the range reader says ${range} ${expected ? 'excludes' : 'admits'} ${DEBIAN_12.node}`);
}

function checkTheLockfile(webDir) {
  const lockfile = JSON.parse(fs.readFileSync(path.join(webDir, 'package-lock.json'), 'utf8'));
  const failures = [];
  if (lockfile.lockfileVersion > NEWEST_LOCKFILE_NPM_9_READS) {
    failures.push(`package-lock.json: lockfileVersion ${lockfile.lockfileVersion}, npm ${DEBIAN_12.npm} reads up to ${NEWEST_LOCKFILE_NPM_9_READS}`);
  }
  let checked = 0;
  for (const [where, entry] of Object.entries(lockfile.packages ?? {})) {
    for (const tool of ['node', 'npm']) {
      const range = entry.engines?.[tool];
      if (range === undefined) continue;
      ++checked;
      if (!admits(range, DEBIAN_12[tool])) {
        failures.push(`${where || 'package.json'}: engines.${tool} "${range}" excludes Debian 12's ${tool} ${DEBIAN_12[tool]}`);
      }
    }
  }
  if (checked === 0) failures.push('package-lock.json: no package declares engines; nothing was checked');
  return { failures, checked };
}

const webDir = process.argv[2];
if (!webDir) {
  console.error('usage: node lockfile_engines_test.mjs WEB_DIR');
  process.exit(2);
}
const { failures, checked } = checkTheLockfile(webDir);
failures.unshift(...checkTheReader());
for (const failure of failures) console.error(`FAIL: ${failure}`);
console.log(`${checked} engines ranges checked against node ${DEBIAN_12.node} and npm ${DEBIAN_12.npm}: ` +
  `${failures.length === 0 ? 'all admit them' : `${failures.length} failures`}`);
process.exit(failures.length === 0 ? 0 : 1);
