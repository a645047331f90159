package dev.motionfusion.core.eval

import dev.motionfusion.core.filter.MadgwickFilter
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assumptions.assumeTrue
import org.junit.jupiter.api.DynamicTest
import org.junit.jupiter.api.TestFactory
import java.io.File

/**
 * A raw magnetometer (its hard-iron offset never removed) on real recordings: the ADVIO subset's iPhone field with
 * the device's offset added back (meta.json `hard_iron_uT`, ~630 µT). Such a field is no heading; the filter must
 * run as it runs without a magnetometer (bit for bit), where a filter that used it would be tens of degrees off
 * (VQF 9D: 69°, the subset's README). On the calibrated field of the same recordings the limit never acts.
 */
class RawMagnetometerTest {
    @TestFactory
    fun `a raw field replays as no field, and the calibrated field is used`(): List<DynamicTest> {
        val dir = PeerFigures.data?.resolve("advio-subset")?.toFile()
        val trials = dir?.listFiles { f -> f.isDirectory }?.sortedBy { it.name }.orEmpty()
        return listOf(DynamicTest.dynamicTest("ADVIO subset present") {
            assumeTrue(dir != null && dir.isDirectory, "no ../shared/data/advio-subset beside the repository: not evaluated")
            assertEquals(11, trials.size, "trials in the ADVIO subset")
        }) + trials.map { trial ->
            DynamicTest.dynamicTest(trial.name) {
                val offset = hardIron(File(trial, "meta.json"))
                val raw = MadgwickFilter()
                val none = MadgwickFilter()
                val calibrated = MadgwickFilter()
                val a = DoubleArray(4)
                val b = DoubleArray(4)
                var rows = 0
                Trial.load(trial).open().use { r ->
                    assertTrue(r.hasMag, "${trial.name} has a magnetometer")
                    while (r.next()) {
                        val v = r.imu
                        val t = Math.round(r.timeS * 1e9)
                        raw.update(t, v[0], v[1], v[2], v[3], v[4], v[5], v[6] + offset[0], v[7] + offset[1], v[8] + offset[2])
                        none.update(t, v[0], v[1], v[2], v[3], v[4], v[5])
                        calibrated.update(t, v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8])
                        raw.orientationInto(a)
                        none.orientationInto(b)
                        if (!a.contentEquals(b)) throw AssertionError("${trial.name} row $rows: the raw field entered the estimate (${a.toList()} against ${b.toList()})")
                        rows++
                    }
                }
                assertTrue(rows > 1000, "${trial.name}: $rows rows")
                assertEquals(raw.diagnostics().gyroscopeSteps, raw.diagnostics().magneticRejections, "${trial.name}: every step's raw reading refused")
                assertEquals(0L, calibrated.diagnostics().magneticRejections, "${trial.name}: the calibrated field is never refused")
            }
        }
    }

    private fun hardIron(meta: File): DoubleArray {
        val m = Regex("\"hard_iron_uT\"\\s*:\\s*\\[([^]]*)]").find(meta.readText()) ?: throw AssertionError("$meta: no hard_iron_uT")
        return m.groupValues[1].split(',').map { it.trim().toDouble() }.toDoubleArray().also { assertEquals(3, it.size) }
    }
}
