// Page furniture of TI documents as `pdftotext -layout` prints it: the lines that repeat on every page and
// belong to no table. Import skips them, so a table that continues on the next page reads as one table.
//
// A line is furniture when it holds (anywhere, since pdftotext puts the left and right parts of a header or
// footer on one line):
// - "www.ti.com" (page header);
// - "Texas Instruments Incorporated" (the copyright line);
// - "Submit Document Feedback" or "Product Folder Links" (footer links);
// - a literature number followed by a dash and a month or year ("SLUUBY2B – SEPTEMBER 2020 – REVISED MAY
//   2022", "SLUUAQ3A – April 2016"): the document id in the footer;
// or when it is nothing but a page number (up to four digits).
#pragma once

#include <string_view>

namespace regmapgen {

bool isPageFurniture(std::string_view line);

// "Table 13-1. Data Memory Table (continued)": the caption TI repeats above a table continued on a new page.
bool isContinuedCaption(std::string_view line);

// "Table 13-1. Data Memory Table" (any table caption, continued or not): "Table", a number with an optional
// "-n", then '.' ("Table 4-5 provides further details." is a sentence, not a caption).
bool isTableCaption(std::string_view line);

// A caption without its surrounding blanks and without " (continued)": "Table 13-1. Data Memory Table".
std::string_view captionText(std::string_view line);

// "13.2.1.1 Calibration:Voltage:Cell 1 Gain", "13.4 0x03 BatteryMode()", "3.4 Write VCell Mode": a numbered
// section heading (at the margin, two or more numbers joined by '.', then the title; table-of-contents lines,
// which end in dot leaders and a page number, are not).
bool isSectionHeading(std::string_view line);

}  // namespace regmapgen
