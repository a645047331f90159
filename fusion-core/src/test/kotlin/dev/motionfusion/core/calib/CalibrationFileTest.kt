package dev.motionfusion.core.calib

import dev.motionfusion.core.Vector3
import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionCalibration
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionReader
import dev.motionfusion.core.session.SessionRecovery
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.SessionWriter
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.lang.management.ManagementFactory

class CalibrationFileTest {
    @TempDir
    lateinit var tmp: Path

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

    @Test
    fun `a session's meta_json carries the calibration, read back by the session reader, and tolerates its absence`() {
        val dir = tmp.resolve("s")
        val meta = SessionMetadata(source = "test", startAnchor = ClockAnchor(0L, 1L), calibration = SessionCalibration(calibration, true), stillRecording = true)
        SessionWriter.create(dir, meta).use { it.gyroscope(10L, 0.1f, 0.2f, 0.3f, 3) }
        SessionReader.open(dir).use { r ->
            assertEquals(SessionCalibration(calibration, true), r.metadata.calibration)
            assertTrue(r.metadata.stillRecording)
        }
        val file = dir.resolve(SessionMetadata.FILE_NAME)
        val text = String(Files.readAllBytes(file), Charsets.UTF_8)
        assertTrue("\"applied_in_live_filter\": true" in text, text)
        assertTrue("\"format\": \"motion-fusion-calibration\"" in text, text)

        // A recovered session (meta.json rewritten) keeps it.
        val killed = tmp.resolve("killed")
        val w = SessionWriter.create(killed, meta.copy(calibration = SessionCalibration(calibration, false)))
        w.gyroscope(10L, 0.1f, 0.2f, 0.3f, 3)
        w.flush()
        w.abandon()
        SessionRecovery.recover(killed)
        SessionReader.open(killed).use { assertEquals(SessionCalibration(calibration, false), it.metadata.calibration) }

        // A meta.json of before the member (or of another writer) has none.
        val old = text.lines().filterNot { "\"still_recording\"" in it }.joinToString("\n")
            .replace(Regex(",\\s*\"calibration\": \\{.*\\}\\s*}\\s*$", RegexOption.DOT_MATCHES_ALL), "\n}\n")
        assertFalse("calibration" in old, old)
        Files.write(file, old.toByteArray(Charsets.UTF_8))
        SessionReader.open(dir).use { r ->
            assertEquals(null, r.metadata.calibration)
            assertFalse(r.metadata.stillRecording)
        }

        // A broken member names its path and position in meta.json.
        val broken = text.replace("[35.0, -20.0, 60.0]", "[35.0, -20.0]")
        Files.write(file, broken.toByteArray(Charsets.UTF_8))
        val e = assertThrows(DataFormatException::class.java) { SessionReader.open(dir) }
        assertTrue("calibration.magnetometer.offset_uT: expected 3 numbers" in e.reason, e.reason)
        assertEquals(broken.lines().indexOfFirst { "[35.0, -20.0]" in it } + 1L, e.line)
        assertTrue(e.message!!.contains(SessionMetadata.FILE_NAME), e.message)
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
