// One Lighthouse accessibility audit of URL in Chromium, with the page's colour scheme set:
//   node bench/a11y/lighthouse_one.mjs URL light|dark mobile|desktop
// Prints one JSON line: score (0-100), the failed audits, and what the page showed (the scheme
// the page saw and its background), so a dark run is known to have been dark.
import lighthouse from "lighthouse";
import desktop from "lighthouse/core/config/desktop-config.js";
import * as chromeLauncher from "chrome-launcher";
import puppeteer from "puppeteer-core";

const [url, scheme, form] = process.argv.slice(2);
const chrome = await chromeLauncher.launch({
  chromePath: process.env.CHROME_PATH || "/usr/bin/chromium",
  chromeFlags: ["--headless=new", "--no-sandbox", "--disable-gpu", "--no-first-run"],
});
try {
  const browser = await puppeteer.connect({ browserURL: `http://127.0.0.1:${chrome.port}` });
  const page = await browser.newPage();
  await page.emulateMediaFeatures([{ name: "prefers-color-scheme", value: scheme }]);
  const flags = { onlyCategories: ["accessibility"], output: "json", logLevel: "error" };
  const result = await lighthouse(url, flags, form === "desktop" ? desktop : undefined, page);
  const lhr = result.lhr;
  const failed = Object.values(lhr.audits)
    .filter((a) => a.scoreDisplayMode === "binary" && a.score === 0)
    .map((a) => a.id);
  const seen = await page.evaluate(() => [
    matchMedia("(prefers-color-scheme: dark)").matches ? "dark" : "light",
    getComputedStyle(document.body).backgroundColor,
  ]);
  if (lhr.runtimeError) throw new Error(`${lhr.runtimeError.code}: ${lhr.runtimeError.message}`);
  console.log(JSON.stringify({ score: Math.round(lhr.categories.accessibility.score * 100), failed, seen }));
  await browser.disconnect();
} finally {
  await chrome.kill();
}
