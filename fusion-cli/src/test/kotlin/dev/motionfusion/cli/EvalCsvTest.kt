package dev.motionfusion.cli

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Path

/** `fusion eval --csv`: the same figures as the Markdown table, as CSV a script reads without parsing Markdown. */
class EvalCsvTest {
    @TempDir
    lateinit var tmp: Path

    private fun p(name: String) = tmp.resolve(name).toString()

    private fun ok(vararg args: String): CliResult = fusion(*args).also { assertEquals(ExitCode.OK, it.code, it.err) }

    /** The per-trial rows of a Markdown table, as lists of cells without the bold marks. */
    private fun markdownRows(out: String) = out.lines().filter { it.startsWith("| ") && !it.startsWith("| trial") && !it.startsWith("| still") }
        .map { row -> row.trim('|').split('|').map { it.trim().trim('*') } }

    @Test
    fun `trials and sessions give one CSV row each with the Markdown table's figures`() {
        for (k in 1..2) ok("simulate", "--duration", "20", "--seed", "$k", "-o", p("s$k"))
        val md = markdownRows(ok("eval", p("s1"), p("s2")).out)
        val csv = ok("eval", "--csv", p("s1"), p("s2")).out.lines().filter { it.isNotEmpty() }
        assertEquals("trial,total_deg,heading_deg,inclination_deg", csv[0])
        assertEquals(3, csv.size, "a header and one row per session, no mean row")
        for (i in 1..2) {
            val c = csv[i].split(',')
            assertEquals(md[i - 1][0], c[0])
            for (j in 1..3) assertEquals(md[i - 1][j].toDouble(), c[j].toDouble(), 0.005001, "column $j of ${c[0]}")
        }
        assertEquals(md[2][1].toDouble(), (csv[1].split(',')[1].toDouble() + csv[2].split(',')[1].toDouble()) / 2, 0.005001, "the Markdown mean")
    }

    @Test
    fun `an orientation against a truth table, and the tilt check, in CSV`() {
        ok("simulate", "--duration", "20", "-o", p("s"))
        ok("replay", "--quiet", p("s"), "-o", p("o.csv"), "--rows", p("rows.csv"))
        val truth = ok("eval", "--csv", "--truth", p("o.csv"), p("o.csv")).out.lines().filter { it.isNotEmpty() }
        assertEquals(listOf("trial,total_deg,heading_deg,inclination_deg", "o.csv,0.000000,0.000000,0.000000"), truth)
        val tilt = ok("eval", "--csv", "--rows", p("rows.csv"), "--after", "5:10", p("o.csv")).out.lines().filter { it.isNotEmpty() }
        assertEquals("still_samples,still_tilt_median_deg,after_motion_samples,after_motion_tilt_median_deg", tilt[0])
        val cells = tilt[1].split(',')
        val md = markdownRows(ok("eval", "--rows", p("rows.csv"), "--after", "5:10", p("o.csv")).out).single()
        assertEquals(md[0], cells[0])
        assertEquals(md[2], cells[2])
        assertEquals(md[3].toDouble(), cells[3].toDouble(), 0.005001)
    }
}
