package dev.motionfusion.core.session

import dev.motionfusion.core.event.SensorEvents
import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.filter.FilterSettings
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.io.DataFormatException
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertThrows
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.nio.file.Files
import java.nio.file.Path
import java.util.Random

class SessionWriterReaderTest {
    @TempDir
    lateinit var tmp: Path

    private val meta = SessionMetadata(
        appVersion = "0.1.0",
        source = "test",
        device = DeviceInfo("Acme", "Phone 1", "14", 34),
        startAnchor = ClockAnchor(1_764_000_000_000L, 5_000_000_000L),
        sensors = listOf(
            SensorInfo(SessionStream.ACCELEROMETER, "acc", "Bosch", 1, maximumRange = 78.4, resolution = 0.0024, powerMa = 0.15,
                minDelayUs = 2500, maxDelayUs = 1_000_000, fifoReservedEventCount = 300, fifoMaxEventCount = 3000, requestedPeriodUs = 5000),
            SensorInfo(SessionStream.GYROSCOPE, "gyro", "Bosch", requestedPeriodUs = 5000),
        ),
        filterSettings = FilterSettings(beta = 0.05, mode = FilterMode.IMU),
    )

    private data class Ev(val s: SessionStream, val t: Long, val v: List<Double>, val a: Int)

    @Test
    fun `every stream round-trips exactly and merges in time order`() {
        val dir = tmp.resolve("s1")
        val r = Random(1)
        val expected = ArrayList<Ev>()
        SessionWriter.create(dir, meta).use { w ->
            var t = 5_000_000_000L
            repeat(3000) { i ->
                t += 1_000_000L + r.nextInt(100_000)
                val f = FloatArray(6) { (r.nextGaussian() * 10).toFloat() }
                val acc = r.nextInt(4)
                when (i % 10) {
                    0 -> w.accelerometer(t, f[0], f[1], f[2], acc)
                    1 -> w.gyroscope(t, f[0], f[1], f[2], acc)
                    2 -> w.magnetometer(t, f[0], f[1], f[2], acc)
                    3 -> w.gyroscopeUncalibrated(t, f[0], f[1], f[2], f[3], f[4], f[5], acc)
                    4 -> w.magnetometerUncalibrated(t, f[0], f[1], f[2], f[3], f[4], f[5], acc)
                    5 -> w.rotationVector(t, f[0], f[1], f[2], f[3], if (i % 20 == 5) Float.NaN else f[4], acc)
                    6 -> w.gameRotationVector(t, f[0], f[1], f[2], f[3], acc)
                    7 -> w.orientation(t, f[0].toDouble(), f[1].toDouble(), f[2].toDouble(), f[3].toDouble())
                    8 -> w.filterDiagnostics(t, f[0].toDouble(), f[1].toDouble(), f[2].toDouble(), true, false, i % 3 == 0)
                    else -> w.write(SessionStream.ROTATION_VECTOR, t, floatArrayOf(f[0], f[1], f[2], f[3]), acc) // no heading accuracy
                }
                val s = listOf(
                    SessionStream.ACCELEROMETER, SessionStream.GYROSCOPE, SessionStream.MAGNETOMETER, SessionStream.GYROSCOPE_UNCALIBRATED,
                    SessionStream.MAGNETOMETER_UNCALIBRATED, SessionStream.ROTATION_VECTOR, SessionStream.GAME_ROTATION_VECTOR,
                    SessionStream.ORIENTATION, SessionStream.FILTER_DIAGNOSTICS, SessionStream.ROTATION_VECTOR,
                )[i % 10]
                val v = when (i % 10) {
                    5 -> (0 until 4).map { f[it].toDouble() } + (if (i % 20 == 5) Double.NaN else f[4].toDouble())
                    8 -> (0 until 3).map { f[it].toDouble() } + listOf(1.0, 0.0, if (i % 3 == 0) 1.0 else 0.0)
                    9 -> (0 until 4).map { f[it].toDouble() } + Double.NaN
                    else -> (0 until s.valueCount).map { f[it].toDouble() }
                }
                expected += Ev(s, t, v, if (s.hasAccuracy) acc else SensorEvents.NO_ACCURACY)
                if (i % 500 == 0) w.flush()
            }
        }
        SessionReader.open(dir).use { reader ->
            assertEquals(meta.device, reader.metadata.device)
            assertEquals(meta.sensors, reader.metadata.sensors)
            assertEquals(meta.filterSettings, reader.metadata.filterSettings)
            assertEquals(meta.startAnchor, reader.metadata.startAnchor)
            assertTrue(reader.metadata.complete)
            assertEquals(300L, reader.metadata.streams[SessionStream.ACCELEROMETER]!!.samples)
            assertEquals(600L, reader.metadata.streams[SessionStream.ROTATION_VECTOR]!!.samples)
            val got = ArrayList<Ev>()
            reader.events().use { e ->
                while (e.next()) got += Ev(e.stream, e.timestampNs, e.values.take(e.stream.valueCount).toList(), e.accuracy)
            }
            assertEquals(expected.size, got.size)
            for (i in expected.indices) {
                val a = expected[i]
                val b = got[i]
                assertEquals(a.s, b.s, "event $i")
                assertEquals(a.t, b.t, "event $i")
                assertEquals(a.a, b.a, "event $i")
                for (k in a.v.indices) assertEquals(a.v[k].toFloat().toRawBits(), b.v[k].toFloat().toRawBits(), "event $i value $k")
            }
        }
    }

    @Test
    fun `equal timestamps put accelerometer and magnetometer before the gyroscope`() {
        val dir = tmp.resolve("s2")
        SessionWriter.create(dir, meta).use { w ->
            w.gyroscope(10, 0f, 0f, 0f, 3)
            w.magnetometer(10, 1f, 0f, 0f, 3)
            w.accelerometer(10, 0f, 0f, 9.8f, 3)
            w.gyroscope(20, 0f, 0f, 0f, 3)
            w.accelerometer(15, 0f, 0f, 9.8f, 3)
        }
        val order = SessionReader.open(dir).use { r -> r.events().use { e -> buildList { while (e.next()) add(e.stream to e.timestampNs) } } }
        assertEquals(
            listOf(SessionStream.ACCELEROMETER to 10L, SessionStream.MAGNETOMETER to 10L, SessionStream.GYROSCOPE to 10L,
                SessionStream.ACCELEROMETER to 15L, SessionStream.GYROSCOPE to 20L),
            order,
        )
    }

    @Test
    fun `files are plain CSV with units in the header`() {
        val dir = tmp.resolve("s3")
        SessionWriter.create(dir, meta).use { w ->
            w.accelerometer(123456789L, 0.1f, -9.80665f, 1e-7f, 3)
            w.rotationVector(123456790L, 0f, 0f, 0.70710677f, 0.70710677f, -1f, 2)
        }
        assertEquals("timestamp_ns,x_m_s2,y_m_s2,z_m_s2,accuracy\n123456789,0.1,-9.80665,0.0000001,3\n", Files.readString(dir.resolve("accelerometer.csv")))
        assertEquals("timestamp_ns,qx,qy,qz,qw,heading_accuracy_rad,accuracy\n123456790,0,0,0.70710677,0.70710677,-1,2\n", Files.readString(dir.resolve("rotation_vector.csv")))
        assertFalse(Files.exists(dir.resolve("gyroscope.csv")), "streams without samples have no file")
        val json = Files.readString(dir.resolve("meta.json"))
        assertTrue(json.contains("\"format_version\": 1"), json)
        assertTrue(json.contains("\"complete\": true"), json)
    }

    @Test
    fun `pauses anchors and stream statistics`() {
        val dir = tmp.resolve("s4")
        SessionWriter.create(dir, meta).use { w ->
            for (k in 0 until 100) w.gyroscope(1_000_000_000L + k * 5_000_000L, 0f, 0f, 0f, 3)
            w.pause(1_600_000_000L)
            w.resume(3_000_000_000L)
            w.anchor(ClockAnchor(1_764_000_060_000L, 65_000_000_000L))
            for (k in 0 until 100) w.gyroscope(3_000_000_000L + k * 5_000_000L, 0f, 0f, 0f, 3)
            w.gyroscope(3_495_000_000L, 0f, 0f, 0f, 3) // duplicate
        }
        val m = SessionReader.open(dir).use { it.metadata }
        assertEquals(listOf(Pause(1_600_000_000L, 3_000_000_000L)), m.pauses)
        assertEquals(1, m.anchors.size)
        val g = m.streams.getValue(SessionStream.GYROSCOPE)
        assertEquals(201L, g.samples)
        assertEquals(200.0, g.achievedRateHz, 1e-6)
        assertEquals(1L, g.duplicates)
        assertEquals(3_495_000_000L, m.endElapsedRealtimeNs)
        assertEquals(1_764_000_000_000.0 + 1000.0, m.startAnchor!!.toWallClockMs(6_000_000_000L))
    }

    @Test
    fun `a killed recording is recovered`() {
        val dir = tmp.resolve("killed")
        val w = SessionWriter.create(dir, meta)
        for (k in 0 until 50) {
            w.accelerometer(k * 10_000_000L, 0f, 0f, 9.81f, 3)
            w.gyroscope(k * 10_000_000L, 0.01f, 0f, 0f, 3)
        }
        w.flush()
        // The process dies: no close(). A partial row reached the gyroscope file.
        Files.write(dir.resolve("gyroscope.csv"), "500000000,0.0".toByteArray(), java.nio.file.StandardOpenOption.APPEND)
        Files.write(dir.resolve("magnetometer.csv"), "timestamp_ns,x_u".toByteArray())
        // The reader already skips the cut line of an unclosed session.
        val beforeRepair = SessionReader.open(dir).use { r -> r.stream(SessionStream.GYROSCOPE).use { e -> var n = 0; while (e.next()) n++; n } }
        assertEquals(50, beforeRepair)
        val report = SessionRecovery.recover(dir)
        assertEquals(13L, report.truncatedBytes[SessionStream.GYROSCOPE])
        assertEquals(0L, report.truncatedBytes[SessionStream.ACCELEROMETER])
        assertTrue(report.metadata.recovered && report.metadata.complete)
        assertTrue(Files.readString(dir.resolve("gyroscope.csv")).endsWith("490000000,0.01,0,0,3\n"))
        assertEquals("timestamp_ns,x_uT,y_uT,z_uT,accuracy\n", Files.readString(dir.resolve("magnetometer.csv")))
        val m = SessionReader.open(dir).use { it.metadata }
        assertTrue(m.recovered)
        assertEquals(50L, m.streams.getValue(SessionStream.GYROSCOPE).samples)
        assertEquals(490_000_000L, m.endElapsedRealtimeNs)
        assertFalse(SessionRecovery.recover(dir).repaired, "a second recovery changes nothing")
    }

    @Test
    fun `slices, end reasons, abandon and interruption`() {
        val dir = tmp.resolve("slices")
        val ring = floatArrayOf(9f, 9f, 0.1f, 0.2f, 0.3f, 0.9f, Float.NaN, 9f)
        SessionWriter.create(dir, meta.copy(sensors = meta.sensors.map { it.copy(stringType = "android.sensor.x") })).use { w ->
            w.write(SessionStream.ROTATION_VECTOR, 5L, ring, 2, 5, 3)
            w.write(SessionStream.GAME_ROTATION_VECTOR, 6L, ring, 2, 3, 1) // one value short
            w.close(7L, "storage_low")
        }
        assertEquals("timestamp_ns,qx,qy,qz,qw,heading_accuracy_rad,accuracy\n5,0.1,0.2,0.3,0.9,,3\n", Files.readString(dir.resolve("rotation_vector.csv")))
        assertEquals("timestamp_ns,qx,qy,qz,qw,accuracy\n6,0.1,0.2,0.3,,1\n", Files.readString(dir.resolve("game_rotation_vector.csv")))
        val m = SessionReader.open(dir).use { it.metadata }
        assertEquals("storage_low", m.endReason)
        assertEquals("android.sensor.x", m.sensors[0].stringType)
        assertFalse(SessionRecovery.isInterrupted(dir))

        val failed = tmp.resolve("failed")
        val w = SessionWriter.create(failed, meta)
        w.gyroscope(1L, 0f, 0f, 0f, 3)
        w.abandon()
        assertThrows(IllegalStateException::class.java) { w.gyroscope(2L, 0f, 0f, 0f, 3) }
        assertTrue(SessionRecovery.isInterrupted(failed))
        assertFalse(SessionRecovery.isInterrupted(tmp.resolve("not-a-session")))
        assertEquals("interrupted", SessionRecovery.recover(failed).metadata.endReason)
        assertEquals("1,0,0,0,3", Files.readAllLines(failed.resolve("gyroscope.csv"))[1])
    }

    @Test
    fun `zip export and import, and reading the zip directly`() {
        val dir = tmp.resolve("zipme")
        SessionWriter.create(dir, meta).use { w -> for (k in 0 until 10) w.gyroscope(k.toLong(), k.toFloat(), 0f, 0f, 3) }
        val zip = tmp.resolve("zipme.zip")
        SessionArchive.zip(dir, zip)
        val count = SessionReader.open(zip).use { r ->
            assertEquals(meta.device, r.metadata.device)
            r.events().use { e -> var n = 0; while (e.next()) { assertEquals(n.toDouble(), e.values[0]); n++ }; n }
        }
        assertEquals(10, count)
        val back = SessionArchive.unzip(zip, tmp.resolve("unzipped"))
        assertEquals(Files.readString(dir.resolve("gyroscope.csv")), Files.readString(back.resolve("gyroscope.csv")))
        assertTrue(SessionReader.isSession(back))
        assertFalse(SessionReader.isSession(tmp.resolve("nothing")))
    }

    @Test
    fun `malformed rows name file line and column`() {
        val dir = tmp.resolve("bad")
        SessionWriter.create(dir, meta).use { w -> w.gyroscope(1, 0f, 0f, 0f, 3) }
        val f = dir.resolve("gyroscope.csv")
        fun errorFor(content: String): DataFormatException {
            Files.writeString(f, content)
            return assertThrows(DataFormatException::class.java) {
                SessionReader.open(dir).use { r -> r.events().use { e -> while (e.next()) Unit } }
            }
        }
        var e = errorFor("timestamp_ns,x_rad_s,y_rad_s,z_rad_s,accuracy\n1,0,0,0,3\n2,0,0,1;5,3\n")
        assertEquals(3L, e.line); assertEquals(7, e.column)
        assertTrue(e.reason.contains("z_rad_s"), e.reason)
        e = errorFor("timestamp_ns,x_rad_s,y_rad_s,accuracy\n")
        assertEquals(1L, e.line)
        assertTrue(e.reason.contains("z_rad_s"), e.reason)
        e = errorFor("timestamp_ns,x_rad_s,y_rad_s,z_rad_s,accuracy\n1,0,0,0,7\n")
        assertEquals(2L, e.line); assertEquals(9, e.column)
        e = errorFor("timestamp_ns,x_rad_s,y_rad_s,z_rad_s,accuracy\n1.5,0,0,0,3\n")
        assertEquals(1, e.column)
        e = errorFor("timestamp_ns,x_rad_s,y_rad_s,z_rad_s,accuracy\n1,0,0\n")
        assertEquals(2L, e.line)
        assertTrue(e.message!!.startsWith(f.toString() + ":2:"), e.message)
    }

    @Test
    fun `meta json errors and newer versions are rejected`() {
        val dir = tmp.resolve("meta")
        SessionWriter.create(dir, meta).close()
        val m = dir.resolve("meta.json")
        val good = Files.readString(m)
        Files.writeString(m, good.replace("\"format_version\": 1", "\"format_version\": 2"))
        assertTrue(assertThrows(DataFormatException::class.java) { SessionReader.open(dir) }.reason.contains("newer"))
        val wrongType = good.replace("\"model\": \"Phone 1\"", "\"model\": 5")
        Files.writeString(m, wrongType)
        val typeError = assertThrows(DataFormatException::class.java) { SessionReader.open(dir) }
        assertTrue(typeError.reason.contains("device.model: expected a string"), typeError.reason)
        // At the member's value: FILE:LINE:COLUMN.
        val at = wrongType.lines().indexOfFirst { "\"model\": 5" in it }
        assertEquals(at + 1L, typeError.line)
        assertEquals(wrongType.lines()[at].indexOf('5') + 1, typeError.column)
        Files.writeString(m, "{\n  \"format_version\": 1,\n  \"device\": {,}\n}")
        val e = assertThrows(DataFormatException::class.java) { SessionReader.open(dir) }
        assertEquals(3L, e.line)
        assertEquals(14, e.column)
    }
}
