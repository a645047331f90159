package dev.motionfusion.core.calib

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.session.SessionStream
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.lang.management.ManagementFactory

class CalibrationFileTest {
    private val calibration = Calibration(
        magnetometer = MagnetometerCalibration(
            SensorCorrection(Vector3(35.0, -20.0, 60.0), Matrix3.symmetric(0.9, 1.1, 1.0, 0.05, -0.02, 0.01)),
            SessionStream.MAGNETOMETER_UNCALIBRATED, EllipsoidModel.FULL, 47.5, 0.4, 0.71, 6000L, 12.0, 0.45,
        ),
        gyroscope = GyroscopeCalibration(Vector3(0.01, -0.02, 0.015), SessionStream.GYROSCOPE_UNCALIBRATED, 27.0, 26, Vector3(1e-5, 2e-5, 3e-5), Vector3(0.004, 0.004, 0.004)),
        accelerometer = null,
        refused = mapOf("accelerometer" to "2 distinct still poses (at least 6 needed)"),
        source = "fusion calibrate 0.1.0",
        recording = "session.zip",
    )

    @Test
    fun `a calibration reads back as written`() {
        val text = CalibrationJson.write(calibration)
        assertEquals(calibration, CalibrationJson.parse(text, "cal.json"))
        assertTrue("\"offset_uT\": [35.0, -20.0, 60.0]" in text, text)
    }

    @Test
    fun `malformed files name the member at fault`() {
        val good = CalibrationJson.write(calibration)
        fun reason(text: String) = assertThrows(DataFormatException::class.java) { CalibrationJson.parse(text, "cal.json") }.message!!
        assertTrue("not a calibration file" in reason("{\"format\": \"motion-fusion-session\", \"format_version\": 1}"))
        assertTrue("newer than this reader" in reason(good.replace("\"format_version\": 1", "\"format_version\": 7")))
        assertTrue("magnetometer.offset_uT: expected 3 numbers" in reason(good.replace("[35.0, -20.0, 60.0]", "[35.0, -20.0]")))
        assertTrue("magnetometer.matrix: not a calibration matrix" in reason(good.replace("[0.9, ", "[-0.9, ")))
        assertTrue("gyroscope.stream: 'magnetometer' is not one of" in reason(good.replace("\"gyroscope_uncalibrated\"", "\"magnetometer\"")))
        assertTrue("cal.json:" in reason(good.dropLast(3)))
        // Member errors carry the position of the member's value.
        val short = good.replace("[35.0, -20.0, 60.0]", "[35.0, -20.0]")
        val e = assertThrows(DataFormatException::class.java) { CalibrationJson.parse(short, "cal.json") }
        val at = short.lines().indexOfFirst { "[35.0, -20.0]" in it }
        assertEquals(at + 1L, e.line)
        assertEquals(short.lines()[at].indexOf('[') + 1, e.column)
        val nonFinite = good.replace("[35.0, -20.0, 60.0]", "[35.0, \"x\", 60.0]")
        val f = assertThrows(DataFormatException::class.java) { CalibrationJson.parse(nonFinite, "cal.json") }
        assertTrue("magnetometer.offset_uT: element 1 is not a finite number" in f.reason, f.reason)
        assertEquals(nonFinite.lines()[f.line.toInt() - 1].indexOf("\"x\"") + 1, f.column)
    }

    /** Events of a list, for the wrapper test. */
    private class ListEvents(private val rows: List<Triple<SessionStream, Long, DoubleArray>>) : SensorEvents {
        private var i = -1
        override fun next() = ++i < rows.size
        override val stream get() = rows[i].first
        override val timestampNs get() = rows[i].second
        override val values get() = rows[i].third
        override val accuracy get() = 3
        override fun close() {}
    }

    @Test
    fun `applied on replay, the uncalibrated streams replace the calibrated ones`() {
        val rows = listOf(
            Triple(SessionStream.ACCELEROMETER, 1L, doubleArrayOf(0.0, 0.0, 9.8)),
            Triple(SessionStream.MAGNETOMETER, 1L, doubleArrayOf(1.0, 2.0, 3.0)),
            Triple(SessionStream.MAGNETOMETER_UNCALIBRATED, 1L, doubleArrayOf(36.0, -19.0, 61.0, 0.0, 0.0, 0.0)),
            Triple(SessionStream.GYROSCOPE_UNCALIBRATED, 1L, doubleArrayOf(0.01, -0.02, 0.015, 0.0, 0.0, 0.0)),
            Triple(SessionStream.GYROSCOPE, 1L, doubleArrayOf(0.5, 0.5, 0.5)),
            Triple(SessionStream.TRUTH, 1L, doubleArrayOf(1.0, 0.0, 0.0, 0.0)),
        )
        val e = CalibratedEvents(ListEvents(rows), calibration, rows.map { it.first }.toSet())
        val out = ArrayList<Pair<SessionStream, List<Double>>>()
        while (e.next()) out += e.stream to e.values.take(3)
        assertEquals(listOf(SessionStream.ACCELEROMETER, SessionStream.MAGNETOMETER, SessionStream.GYROSCOPE, SessionStream.TRUTH), out.map { it.first })
        assertEquals(listOf(0.0, 0.0, 9.8), out[0].second)
        val mag = calibration.magnetometer!!.correction.apply(Vector3(36.0, -19.0, 61.0))
        assertEquals(listOf(mag.x, mag.y, mag.z), out[1].second)
        assertTrue(out[2].second.all { it == 0.0 })
        val missing = assertThrows(IllegalArgumentException::class.java) { CalibratedEvents(ListEvents(rows), calibration, setOf(SessionStream.GYROSCOPE)) }
        assertTrue("magnetometer_uncalibrated, gyroscope_uncalibrated" in missing.message!!, missing.message)
    }

    @Test
    fun `applying a correction allocates nothing`() {
        val bean = ManagementFactory.getThreadMXBean() as com.sun.management.ThreadMXBean
        val c = calibration.magnetometer!!.correction
        val v = DoubleArray(3)
        val calls = 200_000
        fun run() { for (i in 0 until calls) { v[0] = i.toDouble(); v[1] = 1.0; v[2] = 2.0; c.applyInPlace(v) } }
        run()
        val before = bean.currentThreadAllocatedBytes
        run()
        val bytes = bean.currentThreadAllocatedBytes - before
        assertTrue(bytes.toDouble() / calls < 0.05, "$bytes bytes in $calls calls")
        assertFalse(v[0].isNaN())
    }
}
