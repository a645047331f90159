package dev.motionfusion.core.input

import dev.motionfusion.core.io.DataFormatException
import dev.motionfusion.core.session.ClockAnchor
import dev.motionfusion.core.session.SessionArchive
import dev.motionfusion.core.session.SessionMetadata
import dev.motionfusion.core.session.SessionWriter
import dev.motionfusion.core.filter.FilterSettings
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Assertions.fail
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.ByteArrayOutputStream
import java.nio.file.Files
import java.nio.file.Path
import java.util.Random
import java.util.zip.GZIPOutputStream
import java.util.zip.ZipEntry
import java.util.zip.ZipOutputStream

/**
 * Seeded random mutation of valid files of every input format: the readers must finish quickly
 * and either succeed or throw DataFormatException with a source and a reason; nothing else.
 */
class InputFuzzTest {
    @TempDir
    lateinit var tmp: Path

    private val random = Random(20261126)

    private val tokens = listOf(",", "\n", "\r\n", "\"", ";", "NaN", "-", "e", "E999", "1e-400", ".", "9".repeat(40), "\u0000", "\uFEFF", "µ", "-9223372036854775809", " ", "{", "}", "[", "null", "\t")

    private fun mutate(input: ByteArray): ByteArray {
        val b = input.toMutableList()
        repeat(1 + random.nextInt(2)) {
            if (b.isEmpty()) { b.add('x'.code.toByte()); return@repeat }
            val at = random.nextInt(b.size)
            when (random.nextInt(7)) {
                0 -> b[at] = random.nextInt(256).toByte()
                1 -> b[at] = (b[at].toInt() xor (1 shl random.nextInt(8))).toByte()
                2 -> b.add(at, random.nextInt(256).toByte())
                3 -> repeat(minOf(b.size - at, 1 + random.nextInt(20))) { b.removeAt(at) }
                4 -> { val n = minOf(b.size - at, 1 + random.nextInt(40)); b.addAll(at, b.subList(at, at + n).toList()) }
                5 -> while (b.size > at) b.removeAt(b.size - 1)
                else -> b.addAll(at, tokens[random.nextInt(tokens.size)].toByteArray().toList())
            }
        }
        return b.toByteArray()
    }

    private fun gzip(bytes: ByteArray): ByteArray = ByteArrayOutputStream().also { o -> GZIPOutputStream(o).use { it.write(bytes) } }.toByteArray()

    private fun zip(entries: Map<String, ByteArray>): ByteArray = ByteArrayOutputStream().also { o ->
        ZipOutputStream(o).use { z -> for ((n, c) in entries) { z.putNextEntry(ZipEntry(n)); z.write(c); z.closeEntry() } }
    }.toByteArray()

    private fun row3(t: Int) = "${0.01 * t},${0.1 * (t % 7)},${-0.2},${9.8 - 0.01 * t}"

    private val table = ("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n" + (0 until 40).joinToString("") { t -> "${0.01 * t},0.01,-0.02,0.03,0.1,0.2,9.8,20,0,-40\n" }).toByteArray()
    private val phyphoxGyro = ("\"Time (s)\",\"Gyroscope x (rad/s)\",\"Gyroscope y (rad/s)\",\"Gyroscope z (rad/s)\"\n" + (0 until 40).joinToString("") { "${0.01 * it},${0.01 * (it % 7)},-0.02,0.3\n" }).toByteArray()
    private val phyphoxCombined = ("\"Time (s)\",\"Acceleration x (m/s^2)\",\"Acceleration y (m/s^2)\",\"Acceleration z (m/s^2)\",\"Gyroscope x (rad/s)\",\"Gyroscope y (rad/s)\",\"Gyroscope z (rad/s)\"\n" +
        (0 until 40).joinToString("") { row3(it) + ",0.01,0.02,-0.03\n" }).toByteArray()
    private val phyphoxAcc = ("\"Time (s)\";\"Acceleration x (m/s^2)\";\"Acceleration y (m/s^2)\";\"Acceleration z (m/s^2)\"\n" +
        (0 until 40).joinToString("") { row3(it).replace(',', ';').replace('.', ',') + "\n" }).toByteArray()
    private fun logger(order: String, values: String = "0.1,-0.2,9.8") = ("time,seconds_elapsed,$order\n" + (0 until 40).joinToString("") { t -> "${1_700_000_000_000_000_000L + t * 10_000_000L},${0.01 * t},$values\n" }).toByteArray()
    private val truth = ("t_s,qw,qx,qy,qz,movement\n" + (0 until 40).joinToString("") { t -> "${0.01 * t},1,0,0,0,${t % 2}\n" }).toByteArray()

    private fun sessionFiles(): Map<String, ByteArray> {
        val dir = tmp.resolve("seed-session")
        SessionWriter.create(dir, SessionMetadata(appVersion = "1", startAnchor = ClockAnchor(1L, 0L), filterSettings = FilterSettings())).use { w ->
            for (k in 0 until 30) {
                w.accelerometer(k * 10_000_000L, 0.1f, 0.2f, 9.8f, 3)
                w.magnetometer(k * 10_000_000L + 1, 20f, 0f, -40f, 2)
                w.gyroscope(k * 10_000_000L + 2, 0.01f, -0.02f, 0.03f, 3)
                if (k % 3 == 0) w.rotationVector(k * 10_000_000L, 0f, 0f, 0.1f, 0.99498f, -1f, 3)
            }
        }
        return Files.list(dir).use { s -> s.toList() }.associate { it.fileName.toString() to Files.readAllBytes(it) }
    }

    private var case = 0
    private val outcomes = HashMap<String, IntArray>() // [read fine, DataFormatException]

    /** Runs [read] on the mutated input; only DataFormatException may escape. */
    private fun check(format: String, read: () -> Unit) {
        case++
        val o = outcomes.getOrPut(format) { IntArray(2) }
        try {
            read()
            o[0]++
        } catch (e: DataFormatException) {
            o[1]++
            assertTrue(e.source.isNotEmpty() && e.reason.isNotEmpty(), "$format case $case: empty source or reason: ${e.message}")
        } catch (e: Throwable) {
            fail<Unit>("$format case $case: ${e::class.java.name}: ${e.message}", e)
        }
    }

    private fun drain(p: Path) {
        Recording.open(p).use { r -> r.events().use { e -> var n = 0L; while (e.next()) { n++; e.timestampNs; e.values } } }
    }

    private fun write(name: String, bytes: ByteArray): Path {
        val p = tmp.resolve("case$case-$name")
        Files.write(p, bytes)
        return p
    }

    @Test
    fun `mutated inputs of every format never crash or hang`() {
        val session = sessionFiles()
        val rounds = 250
        repeat(rounds) {
            check("table") { drain(write("t.csv", mutate(table))) }
            check("table.gz") { drain(write("t.csv.gz", if (random.nextBoolean()) mutate(gzip(table)) else gzip(mutate(table)))) }
            check("table.gz of members") {
                // cat a.gz b.gz [c.gz]: one member of the concatenation mutated, or the whole.
                val cuts = (1..1 + random.nextInt(2)).map { random.nextInt(table.size) }.sorted()
                val parts = (listOf(0) + cuts).zip(cuts + table.size).map { (a, b) -> gzip(table.copyOfRange(a, b)) }
                val victim = random.nextInt(parts.size + 1)
                val bytes = parts.mapIndexed { i, g -> if (i == victim) mutate(g) else g }.reduce { a, b -> a + b }
                drain(write("members.csv.gz", if (victim == parts.size) mutate(bytes) else bytes))
            }
            check("session zip directory") {
                // A byte of the central directory or of a local header changed: the two must agree.
                val z = zip(session.mapKeys { "s/${it.key}" })
                val cd = ((z.size - 22) downTo 0).first { z[it] == 0x50.toByte() && z[it + 1] == 0x4b.toByte() && z[it + 2] == 5.toByte() && z[it + 3] == 6.toByte() }
                    .let { e -> (0 until 4).sumOf { (z[e + 16 + it].toInt() and 0xff) shl (8 * it) } }
                val at = if (random.nextBoolean()) cd + random.nextInt(z.size - cd) else random.nextInt(30)
                drain(write("directory.zip", z.copyOf().also { it[at] = (it[at].toInt() xor (1 shl random.nextInt(8))).toByte() }))
            }
            check("truth") { QuaternionTableReader.open(write("truth.csv", mutate(truth))).use { r -> while (r.next()) r.q } }
            check("phyphox csv") { drain(write("Raw Data.csv", mutate(phyphoxCombined))) }
            check("phyphox zip") {
                val entries = if (random.nextBoolean()) mapOf("Gyroscope.csv" to mutate(phyphoxGyro), "Accelerometer.csv" to phyphoxAcc)
                else mapOf("Gyroscope.csv" to phyphoxGyro, "Accelerometer.csv" to mutate(phyphoxAcc))
                drain(write("phyphox.zip", if (random.nextInt(4) == 0) mutate(zip(entries)) else zip(entries)))
            }
            check("sensor logger zip") {
                val acc = if (random.nextBoolean()) mapOf("TotalAcceleration.csv" to logger("z,y,x"))
                else mapOf("Accelerometer.csv" to logger("z,y,x", "0.05,-0.1,0.2"), "Gravity.csv" to logger("z,y,x"))
                // Plausible rates (rad/s): a gyroscope reading |ω| ≈ 9.8 would be taken for °/s.
                val files = acc + mapOf("Gyroscope.csv" to logger("z,y,x", "0.01,-0.02,0.03"),
                    "Orientation.csv" to String(logger("qz,qy,qx")).replace("\n", ",1\n").replaceFirst("qx,1", "qx,qw").toByteArray())
                val victim = files.keys.toList()[random.nextInt(files.size)]
                val entries = files.mapValues { (n, c) -> if (n == victim) mutate(c) else c }
                drain(write("logger.zip", if (random.nextInt(4) == 0) mutate(zip(entries)) else zip(entries)))
            }
            check("session folder") {
                val dir = Files.createDirectories(tmp.resolve("case$case-session"))
                val victim = session.keys.toList()[random.nextInt(session.size)]
                for ((n, c) in session) Files.write(dir.resolve(n), if (n == victim) mutate(c) else c)
                drain(dir)
            }
            check("session zip") {
                val dir = tmp.resolve("case$case-s")
                val victim = session.keys.toList()[random.nextInt(session.size)]
                val entries = session.mapKeys { "s/${it.key}" }.mapValues { (n, c) -> if (n == "s/$victim") mutate(c) else c }
                val bytes = if (random.nextInt(3) == 0) mutate(zip(entries)) else zip(entries)
                val z = write("session.zip", bytes)
                drain(z)
                try {
                    SessionArchive.unzip(z, dir)
                } catch (e: DataFormatException) {
                    throw e
                }
            }
        }
        println("fuzz: $case cases; per format [read fine, DataFormatException]: " + outcomes.entries.joinToString { "${it.key} ${it.value.toList()}" })
        // The mutations must exercise both outcomes of every reader, or the test proves little.
        for ((f, o) in outcomes) assertTrue(o[0] > 0 && o[1] > 0, "$f: ${o.toList()}")
    }

    /**
     * Plausibility (docs/IMPORT.md): seeded faults of the values rather than the bytes (a column in
     * another unit, times scaled, reversed, stalled or going back, single readings beyond any
     * phone's range). Each replay either fails with a DataFormatException or gives finite
     * orientations only, with every impossible reading counted as skipped.
     */
    @Test
    fun `a bit flipped in compressed data is named as damage, not as the CSV error it causes`() {
        // A bigger table, so that most flips land in deflated data that still decodes (to garbage).
        val big = ("t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n" + (0 until 2000).joinToString("") { t -> "${0.01 * t},0.01,-0.02,0.03,0.1,0.2,9.8,20,0,-40\n" }).toByteArray()
        val packed = gzip(big)
        var csvErrors = 0
        for (k in 0 until 40) {
            val at = 20 + (k * 7919) % (packed.size - 40)
            val bad = packed.copyOf().also { it[at] = (it[at].toInt() xor (1 shl (k % 8))).toByte() }
            val p = tmp.resolve("flip$k.csv.gz")
            Files.write(p, bad)
            val e = try {
                drain(p)
                null
            } catch (e: DataFormatException) {
                e
            } ?: continue // a flip in a digit that still parses: the CRC-32 at the end catches it (below)
            val m = e.message!!
            if ("damaged compressed data" in m) csvErrors++
            assertTrue("CRC-32" in m || "damaged compressed data" in m || "invalid" in m.lowercase() || "corrupt" in m.lowercase() || "gzip" in m.lowercase(),
                "flip at byte $at: $m")
        }
        assertTrue(csvErrors > 0, "no flip read as a CSV error first: the case is not exercised")
    }

    @Test
    fun `implausible values are an error or skipped, never a silent NaN`() {
        val base = (0 until 400).map { i -> doubleArrayOf(i * 0.01, 0.01, -0.02, 0.3, 0.1, 0.2, 9.8, 20.0, 0.0, -40.0) }
        val scales = listOf(1e-3, 1e-2, 1e-1, 1.0 / 9.80665, 180 / Math.PI, 100.0, 1000.0, 1e6, 1e9)
        val huge = listOf(1e308, -1e308, 3.4028235e38, 1e30, 1e6, 200.0, -600.0, 6000.0)
        val outcome = IntArray(2)
        repeat(300) {
            val rows = base.map { it.copyOf() }.toMutableList()
            var impossible = 0
            when (random.nextInt(6)) {
                0 -> { val s = scales[random.nextInt(scales.size)]; rows.forEach { it[0] *= s } }
                1 -> rows.reverse()
                2 -> { val from = random.nextInt(rows.size); rows.drop(from).forEach { it[0] = rows[from][0] } }
                3 -> { val from = 1 + random.nextInt(rows.size - 1); val back = random.nextDouble() * 10; rows.drop(from).forEach { it[0] -= back } }
                4 -> { val col = 1 + 3 * random.nextInt(3); val s = scales[random.nextInt(scales.size)]; rows.forEach { for (k in col until col + 3) it[k] *= s } }
                else -> repeat(1 + random.nextInt(3)) {
                    val col = 1 + random.nextInt(9)
                    val v = huge[random.nextInt(huge.size)]
                    val limit = if (col <= 3) 100.0 else if (col <= 6) 490.3325 else 5000.0
                    val r = rows[random.nextInt(rows.size)]
                    if (Math.abs(r[col]) <= limit && Math.abs(v) > limit) impossible++
                    r[col] = v
                }
            }
            val text = rows.joinToString("", "t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n") { r -> r.joinToString(",", postfix = "\n") }
            case++
            try {
                Recording.open(write("p.csv", text.toByteArray())).use { rec ->
                    var nan = 0
                    val replayer = dev.motionfusion.core.replay.Replayer()
                    rec.events().use { e ->
                        replayer.run(e, rec.originNs, object : dev.motionfusion.core.replay.ReplayListener {
                            override fun step(step: dev.motionfusion.core.replay.ReplayStep) { if (step.initialised && step.orientation.any { !it.isFinite() }) nan++ }
                        }, source = rec.name)
                    }
                    assertTrue(nan == 0, "case $case: $nan non-finite orientations")
                    assertTrue(replayer.filter.diagnostics().skippedOutOfRange >= impossible, "case $case: $impossible impossible readings, ${replayer.filter.diagnostics().skippedOutOfRange} skipped")
                }
                outcome[0]++
            } catch (e: DataFormatException) {
                outcome[1]++
                assertTrue(e.source.isNotEmpty() && e.reason.isNotEmpty(), "case $case: ${e.message}")
            }
        }
        println("plausibility fuzz: 300 cases; [replayed, DataFormatException]: ${outcome.toList()}")
        assertTrue(outcome[0] > 0 && outcome[1] > 0, outcome.toList().toString())
    }

    /** [read] must fail with a DataFormatException whose message contains [fragment] and stays short. */
    private fun rejects(fragment: String, read: () -> Unit) {
        case++
        try {
            read()
            fail<Unit>("case $case: read fine, expected an error with '$fragment'")
        } catch (e: DataFormatException) {
            assertTrue(e.message!!.contains(fragment), "case $case: ${e.message}")
            assertTrue(e.message!!.length < 600, "case $case: message of ${e.message!!.length} characters")
        }
    }

    @Test
    fun `hostile files are clear errors, never a crash or unbounded memory`() {
        val zeros = ByteArray(8 shl 20) // 8 MiB without a newline: compresses to a few KiB
        val header = "t_s,gx,gy,gz,ax,ay,az\n".toByteArray()
        rejects("longer than") { drain(write("long.csv", header + ByteArray(3 shl 20) { 'x'.code.toByte() })) }
        rejects("longer than") { drain(write("bomb.csv.gz", gzip(header + zeros))) }
        rejects("longer than") { drain(write("bomb.zip", zip(mapOf("Gyroscope.csv" to logger("z,y,x") + zeros, "TotalAcceleration.csv" to logger("z,y,x"))))) }
        val big = ByteArrayOutputStream().also { o -> o.write(header); repeat(100_000) { i -> o.write("${0.01 * i},0,0,0,0,0,9.8\n".toByteArray()) } }.toByteArray()
        val small = ImportOptions(dev.motionfusion.core.io.InputLimits.perFile(1 shl 20))
        rejects("limit for one file") { Recording.open(write("big.csv.gz", gzip(big)), small).use { r -> r.events().use { e -> while (e.next()) Unit } } }
        // A limit smaller than what sniffing the format reads: the limit is named, not "not a recognised input".
        rejects("limit for one file") { Recording.open(write("tiny-limit.csv.gz", gzip(big)), ImportOptions(dev.motionfusion.core.io.InputLimits.perFile(64))).use { } }
        rejects("in total") {
            Recording.open(write("big.zip", zip(mapOf("Gyroscope.csv" to logger("z,y,x"), "TotalAcceleration.csv" to logger("z,y,x")))),
                ImportOptions(dev.motionfusion.core.io.InputLimits(maxEntryBytes = 2000, maxTotalBytes = 3000))).use { r -> r.events().use { e -> while (e.next()) Unit } }
        }
        rejects("empty: nothing was read from it") { drain(write("empty.csv", ByteArray(0))) }
        rejects("mx,my,mz are empty in every row") { drain(write("nomag.csv", "t_s,gx,gy,gz,ax,ay,az,mx,my,mz\n0,0,0,0,0,0,9.8,,,\n0.01,0,0,0,0,0,9.8,,,\n".toByteArray())) }
        rejects("3 fields") { drain(write("short.csv", "t_s,gx,gy,gz,ax,ay,az\n1,2,3\n".toByteArray())) }
        rejects("has 7") { drain(write("extra2.csv", "t_s,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,9.8,1\n".toByteArray())) }
        rejects("decimal comma") { drain(write("comma.csv", "t_s,gx,gy,gz,ax,ay,az\n0,0,0,0,0,0,9,8\n".toByteArray())) }
        rejects("integer nanoseconds") {
            drain(write("float.zip", zip(mapOf("Gyroscope.csv" to "time,seconds_elapsed,z,y,x\n1.7e18,0,0,0,0\n".toByteArray(), "TotalAcceleration.csv" to logger("z,y,x")))))
        }
        rejects("not a finite time") { drain(write("nan.csv", "t_s,gx,gy,gz,ax,ay,az\nNaN,0,0,0,0,0,9.8\n".toByteArray())) }
        rejects("larger than") {
            val dir = Files.createDirectories(tmp.resolve("bigmeta"))
            Files.write(dir.resolve("meta.json"), ByteArray(2 shl 20) { ' '.code.toByte() })
            drain(dir)
        }
        rejects("without gyroscope") { drain(write("Accelerometer.csv", phyphoxAcc)) }
        rejects("without accelerometer") { drain(write("Gyroscope.csv", phyphoxGyro)) }
        rejects("holds 2 recordings") {
            val dir = Files.createDirectories(tmp.resolve("two"))
            for (n in listOf("a", "b")) Files.write(Files.createDirectories(dir.resolve(n)).resolve("t.csv"), table)
            drain(dir)
        }
        // Two tables side by side in one folder, or beside a session: each named, none read in the other's place.
        rejects("holds 2 recordings (a.csv, b.csv)") {
            val dir = Files.createDirectories(tmp.resolve("side"))
            for (n in listOf("a", "b")) Files.write(dir.resolve("$n.csv"), table)
            drain(dir)
        }
        rejects("holds 2 recordings (table.csv, s)") {
            val dir = Files.createDirectories(tmp.resolve("beside"))
            Files.write(Files.createDirectories(dir.resolve("s")).resolve("t.csv"), table)
            Files.write(dir.resolve("table.csv"), table)
            drain(dir)
        }
        // Archives that lie: two entries of one name, a damaged second gzip member, trailing garbage.
        rejects("two entries of this name") {
            val twin = zip(mapOf("Gyroscope.csv" to logger("z,y,x"), "Gyroscopf.csv" to logger("z,y,x").copyOf(60), "TotalAcceleration.csv" to logger("z,y,x")))
            val name = "Gyroscopf.csv".toByteArray()
            for (i in 0..twin.size - name.size) if (name.indices.all { twin[i + it] == name[it] }) twin[i + name.size - 5] = 'e'.code.toByte()
            drain(write("twin.zip", twin))
        }
        val half = table.size / 2
        val second = gzip(table.copyOfRange(half, table.size))
        rejects("member 2 (at byte") { drain(write("bad2.csv.gz", gzip(table.copyOfRange(0, half)) + second.copyOf().also { it[0] = 0x1e })) }
        rejects("member 2") { drain(write("bad2data.csv.gz", gzip(table.copyOfRange(0, half)) + second.copyOf().also { it[11] = (it[11].toInt() xor 0xff).toByte(); it[12] = (it[12].toInt() xor 0xff).toByte() })) }
        rejects("not a gzip header") { drain(write("tail.csv.gz", gzip(table) + "trailing".toByteArray())) }
        Recording.open(write("two.csv.gz", gzip(table.copyOfRange(0, half)) + second)).use { r ->
            r.events().use { e -> var n = 0; while (e.next()) n++; assertTrue(n == 40 * 3, "both members read: $n events") }
        }
        println("hostile: $case cases, each a DataFormatException with the expected reason")
    }
}
