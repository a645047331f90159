package dev.motionfusion.core.eval

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Test

/** [Evaluation.csv]: the figures of [Evaluation.table] as plain CSV for scripts (no bold, no mean row). */
class EvaluationCsvTest {
    private val results = listOf(
        TrialResult("01_slow", ErrorRmse(1.23456, 1.0, 0.5, 100)),
        TrialResult("a,b \"c\"", ErrorRmse(2.0, Double.NaN, 0.25, 10)),
    )

    @Test
    fun `one row per trial with six decimals, names with commas or quotes quoted`() {
        assertEquals(
            listOf("trial,total_deg,heading_deg,inclination_deg", "01_slow,1.234560,1.000000,0.500000", "\"a,b \"\"c\"\"\",2.000000,,0.250000"),
            Evaluation.csv(results).lines().filter { it.isNotEmpty() },
        )
    }

    @Test
    fun `the rotation vector's columns follow, empty for a trial without one`() {
        val csv = Evaluation.csv(results, mapOf("01_slow" to ErrorRmse(3.0, 2.5, 1.5, 100))).lines().filter { it.isNotEmpty() }
        assertEquals("trial,total_deg,heading_deg,inclination_deg,rv_total_deg,rv_heading_deg,rv_inclination_deg", csv[0])
        assertEquals("01_slow,1.234560,1.000000,0.500000,3.000000,2.500000,1.500000", csv[1])
        assertEquals("\"a,b \"\"c\"\"\",2.000000,,0.250000,,,", csv[2])
    }

    @Test
    fun `the Markdown table's mean row is bold and absent from the CSV, whose rows give the same figures`() {
        val table = Evaluation.table(results.take(1))
        assertEquals("| **mean** | **1.23** | 1.00 | 0.50 |", table.lines().filter { it.isNotEmpty() }.last())
        assertEquals(2, Evaluation.csv(results.take(1)).lines().count { it.isNotEmpty() })
    }
}
