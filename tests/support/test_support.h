// Shared helpers for the tests (statistics, chi-square).
#pragma once
