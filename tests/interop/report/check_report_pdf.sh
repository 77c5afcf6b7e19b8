#!/usr/bin/env bash
# report.pdf as a PDF reader sees it (Debian's poppler-utils, independent of the weasyprint that
# wrote it): a valid PDF with pages, the export's map views embedded at the sizes report.html
# gives them, the report's text, and page 1 rendered shows the height-coloured top-down map with
# the trajectory (check_screenshot.py, as for the browser's screenshot).
set -euo pipefail
out=$1
here=$(cd "$(dirname "$0")" && pwd)
dir=$out/target/walk
command -v pdfinfo >/dev/null || { echo "poppler-utils is not installed (tools/install-deps)"; exit 77; }
command -v weasyprint >/dev/null || { echo "weasyprint is not installed (tools/install-deps)"; exit 77; }
pdf=$dir/report.pdf
[ -f "$pdf" ] || { echo "no $pdf although weasyprint is installed"; exit 1; }
info=$(pdfinfo "$pdf")  # fails on a file without a readable header, xref or trailer
pages=$(awk '/^Pages:/ {print $2}' <<<"$info")
echo "check_report_pdf: $(stat -c %s "$pdf") bytes, $pages pages, $(grep '^Producer:' <<<"$info")"
[ "$pages" -ge 2 ] || { echo "check_report_pdf: expected at least 2 pages"; exit 1; }
# Every map view of report.html is an image in the PDF at its size.
want=$(grep -Eo '<img [^>]*width="[0-9]+" height="[0-9]+"' "$dir/report.html" |
       sed -E 's/.*width="([0-9]+)" height="([0-9]+)"/\1x\2/' | sort)
have=$(pdfimages -list "$pdf" | awk 'NR > 2 && $3 == "image" {print $4 "x" $5}' | sort)
echo "check_report_pdf: images in report.html: $(echo $want); in report.pdf: $(echo $have)"
[ "$(wc -l <<<"$want")" -ge 4 ] || { echo "check_report_pdf: report.html has fewer than 4 map views"; exit 1; }
[ "$want" = "$have" ] || { echo "check_report_pdf: the PDF's images are not report.html's"; exit 1; }
text=$(pdftotext "$pdf" -)
for phrase in "Scan report: walk" "Sensor health over time" "Degenerate intervals" "30.0 s" \
              "Modules and directions over time" "too_few_correspondences" "45.0 s"; do
  grep -qF "$phrase" <<<"$text" || { echo "check_report_pdf: the text lacks '$phrase'"; exit 1; }
done
rm -f "$out/pdf-page-1.png"
pdftoppm -r 100 -f 1 -l 1 -singlefile -png "$pdf" "$out/pdf-page-1"
/usr/bin/python3 "$here/check_screenshot.py" "$out/pdf-page-1.png"
