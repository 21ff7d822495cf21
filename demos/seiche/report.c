// JUnit XML and TAP reports of scene-script runs. See report.h.
#include "demos/seiche/report.h"

#include <errno.h>
#include <stdio.h>
#include <string.h>

static const char *status_text(int status)
{
    switch (status) {
    case ENG_EXIT_OK: return "ok";
    case ENG_EXIT_CHECK_FAILED: return "a check failed";
    case ENG_EXIT_USAGE: return "usage or script error";
    case ENG_EXIT_NO_COMPUTE: return "no OpenGL 4.3 compute context";
    case ENG_EXIT_DIVERGED: return "the solver diverged";
    case 5: return "GL error or synchronisation hazard"; // ENG_GL_EXIT_STATUS
    case SEICHE_EXIT_PROCESS_ENDED: return "the run's process ended before the run";
    default: return "unknown status";
    }
}

static void xml_text(FILE *f, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        case '\'': fputs("&apos;", f); break;
        default:
            if ((unsigned char)*s < 0x20 && *s != '\n' && *s != '\t') fputc(' ', f);
            else fputc(*s, f);
        }
    }
}

// A file name in an XML attribute: escaped for XML, and its control characters as text
// (eng_app_name_escape), where xml_text would make a newline a space (or a raw one that a
// parser reads as a space).
static void xml_name(FILE *f, const char *s)
{
    char e[5];
    for (; *s; s++) {
        if (eng_app_name_escape((unsigned char)*s, e)) {
            fputs(e, f);
        } else {
            char c[2] = { *s, 0 };
            xml_text(f, c);
        }
    }
}

// A file name in a TAP line: control characters as text, so that the line stays one, and
// '#' as "\#" (TAP 13: a '#' begins a directive, and "# TODO" would excuse a failure).
static void tap_name(FILE *f, const char *s)
{
    char e[5];
    for (; *s; s++) {
        if (eng_app_name_escape((unsigned char)*s, e)) fputs(e, f);
        else if (*s == '#') fputs("\\#", f);
        else fputc(*s, f);
    }
}

// Test cases of one run: its check sites, the checks that never ran, and the run.
static int case_count(const eng_app_report *r) { return r->check_count + r->never_ran_count + 1; }

static int failures_of(const eng_app_report *r)
{
    int n = r->never_ran_count + (r->status != ENG_EXIT_OK);
    for (int i = 0; i < r->check_count; i++) n += r->checks[i].failed > 0;
    return n;
}

static bool finish(FILE *f, const char *path, char *err, size_t err_size)
{
    bool bad = ferror(f) != 0;
    int e = errno;
    if (fclose(f) != 0 && !bad) {
        bad = true;
        e = errno;
    }
    if (bad) snprintf(err, err_size, "writing '%s' failed: %s", path, strerror(e));
    return !bad;
}

bool seiche_write_junit(const char *path, const seiche_run *runs, int count, char *err, size_t err_size)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        snprintf(err, err_size, "cannot write '%s': %s", path, strerror(errno));
        return false;
    }
    int tests = 0, failures = 0;
    double time = 0.0;
    for (int i = 0; i < count; i++) {
        tests += case_count(&runs[i].report);
        failures += failures_of(&runs[i].report);
        time += runs[i].report.wall_s;
    }
    fprintf(f, "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n");
    fprintf(f, "<testsuites name=\"seiche\" tests=\"%d\" failures=\"%d\" time=\"%.3f\">\n", tests, failures, time);
    for (int i = 0; i < count; i++) {
        const eng_app_report *r = &runs[i].report;
        fprintf(f, "  <testsuite name=\"");
        xml_name(f, runs[i].script);
        fprintf(f, "\" tests=\"%d\" failures=\"%d\" time=\"%.3f\">\n", case_count(r), failures_of(r), r->wall_s);
        for (int k = 0; k < r->check_count; k++) {
            const eng_check_site *c = &r->checks[k];
            fprintf(f, "    <testcase classname=\"");
            xml_name(f, runs[i].script);
            fprintf(f, "\" name=\"");
            xml_name(f, c->source[0] ? c->source : runs[i].script);
            fprintf(f, ":%d: seiche.check (%u passed, %u failed)\" time=\"0\"", c->line, c->passed, c->failed);
            if (!c->failed) {
                fprintf(f, "/>\n");
                continue;
            }
            fprintf(f, ">\n      <failure message=\"");
            xml_text(f, c->message);
            fprintf(f, "\"/>\n    </testcase>\n");
        }
        for (int k = 0; k < r->never_ran_count; k++) {
            fprintf(f, "    <testcase classname=\"");
            xml_name(f, runs[i].script);
            fprintf(f, "\" name=\"");
            xml_name(f, runs[i].script);
            fprintf(f, ":%d: seiche.check\" time=\"0\">\n      <failure message=\"never ran: the run ended at frame "
                       "%llu first\"/>\n    </testcase>\n", r->never_ran[k], (unsigned long long)r->frames);
        }
        fprintf(f, "    <testcase classname=\"");
        xml_name(f, runs[i].script);
        fprintf(f, "\" name=\"run (%llu frame%s, %.3f s simulated)\" time=\"%.3f\"", (unsigned long long)r->frames,
                r->frames == 1 ? "" : "s", r->sim_time, r->wall_s);
        if (r->status == ENG_EXIT_OK) {
            fprintf(f, "/>\n");
        } else {
            // The message says what ended the run ("the solver diverged at step 4 ...", "x.lua:2:
            // check failed: ..."); the status's own words only stand in when there is none.
            fprintf(f, ">\n      <failure type=\"exit %d\" message=\"", r->status);
            xml_text(f, r->message[0] ? r->message : status_text(r->status));
            fprintf(f, "\"/>\n    </testcase>\n");
        }
        fprintf(f, "  </testsuite>\n");
    }
    fprintf(f, "</testsuites>\n");
    return finish(f, path, err, err_size);
}

// A TAP diagnostic block with the message as a single-quoted YAML scalar.
static void yaml_message(FILE *f, const char *m)
{
    fputs("  ---\n  message: '", f);
    char e[5];
    for (; *m && *m != '\n'; m++) {
        if (*m == '\'') fputc('\'', f);
        if (eng_app_name_escape((unsigned char)*m, e)) fputs(e, f); // no raw control characters in YAML
        else fputc(*m, f);
    }
    fputs("'\n  ...\n", f);
}

bool seiche_write_tap(const char *path, const seiche_run *runs, int count, char *err, size_t err_size)
{
    FILE *f = fopen(path, "w");
    if (!f) {
        snprintf(err, err_size, "cannot write '%s': %s", path, strerror(errno));
        return false;
    }
    int tests = 0, n = 0;
    for (int i = 0; i < count; i++) tests += case_count(&runs[i].report);
    fprintf(f, "TAP version 13\n1..%d\n", tests);
    for (int i = 0; i < count; i++) {
        const eng_app_report *r = &runs[i].report;
        for (int k = 0; k < r->check_count; k++) {
            const eng_check_site *c = &r->checks[k];
            fprintf(f, "%s %d - ", c->failed ? "not ok" : "ok", ++n);
            tap_name(f, c->source[0] ? c->source : runs[i].script);
            fprintf(f, ":%d: seiche.check (%u passed, %u failed)\n", c->line, c->passed, c->failed);
            if (c->failed) yaml_message(f, c->message);
        }
        for (int k = 0; k < r->never_ran_count; k++) {
            fprintf(f, "not ok %d - ", ++n);
            tap_name(f, runs[i].script);
            fprintf(f, ":%d: seiche.check never ran (the run ended at frame %llu first)\n", r->never_ran[k],
                    (unsigned long long)r->frames);
        }
        fprintf(f, "%s %d - ", r->status == ENG_EXIT_OK ? "ok" : "not ok", ++n);
        tap_name(f, runs[i].script);
        fprintf(f, ": run (exit %d, %s)\n", r->status, status_text(r->status));
        if (r->status != ENG_EXIT_OK && r->message[0]) yaml_message(f, r->message);
    }
    return finish(f, path, err, err_size);
}
