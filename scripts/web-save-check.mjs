// Clicks the web viewer's Save buttons (by their place on the 1280 x 800 page: egui draws into
// a canvas, so there is no element to find) and checks that each offers its download.
//   node scripts/web-save-check.mjs URL OUT_DIR     (needs playwright-core and /usr/bin/chromium)
import { chromium } from "playwright-core";

const [url, out] = process.argv.slice(2);
const browser = await chromium.launch({
  executablePath: "/usr/bin/chromium",
  args: ["--no-sandbox", "--disable-background-networking", "--disable-component-update",
    "--disable-sync", "--disable-quic", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
});
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 800 }, acceptDownloads: true });
  await page.goto(url);
  await page.waitForTimeout(4000);
  for (const [x, y, want] of [[85, 621, "supergrain-state.json"], [31, 621, "supergrain-screenshot.png"]]) {
    const download = page.waitForEvent("download", { timeout: 15000 });
    await page.mouse.click(x, y);
    const d = await download;
    if (d.suggestedFilename() !== want) throw new Error(`offered ${d.suggestedFilename()}, not ${want}`);
    await d.saveAs(`${out}/${want}`);
    console.log(`downloaded ${want}`);
  }
} finally {
  await browser.close();
}
