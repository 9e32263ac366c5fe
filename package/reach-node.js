// `reachProblems(set)` in Node: the set's file read beside this module.
import { readFileSync } from 'node:fs';
import { makeReachProblems } from './reach.js';

const cache = new Map();

export const reachProblems = makeReachProblems((set) => {
  if (!cache.has(set)) {
    cache.set(set, JSON.parse(readFileSync(new URL(`./problems/${set}.json`, import.meta.url), 'utf8')));
  }
  return cache.get(set);
});
