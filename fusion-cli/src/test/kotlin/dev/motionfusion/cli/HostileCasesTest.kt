package dev.motionfusion.cli

import dev.motionfusion.core.io.FileOperations
import dev.motionfusion.core.io.SyncedOutput
import org.junit.jupiter.api.AfterAll
import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.BeforeAll
import org.junit.jupiter.api.DynamicTest
import org.junit.jupiter.api.TestFactory
import org.junit.jupiter.api.TestInstance
import java.io.ByteArrayOutputStream
import java.io.FileOutputStream
import java.io.IOException
import java.io.OutputStream
import java.io.PrintStream
import java.nio.file.AccessDeniedException
import java.nio.file.Files
import java.nio.file.LinkOption
import java.nio.file.Path
import java.nio.file.StandardCopyOption
import java.security.MessageDigest
import java.util.zip.CRC32
import java.util.zip.ZipEntry
import java.util.zip.ZipOutputStream

/**
 * The careless or unlucky user's runs of `fusion` (issue: nothing written is lost, half-written
 * or outside its folder), one generated test per case. Each case runs in a fresh copy of the
 * same folder (sessions, zip, tables, links, interrupted and foreign folders) and checks the exit
 * code, the message, that no stack trace is printed, and, by hashing every file (link targets
 * included) before and after, that nothing but the case's expected output changed.
 */
@TestInstance(TestInstance.Lifecycle.PER_CLASS)
class HostileCasesTest {
    private val tmp: Path = Files.createTempDirectory("fusion-hostile")

    private lateinit var template: Path

    /** Where stdout goes in a case. */
    private enum class Stdout { CAPTURED, BROKEN_PIPE, DEV_FULL }

    /** Storage faults under the command's outputs. */
    private enum class Storage { REAL, FULL_AFTER_2000_BYTES, PERMISSION_DENIED, OUT_OF_MEMORY }

    private class Case(
        val name: String,
        val args: List<String>,
        val code: Int,
        val message: String,
        /** Paths (relative to the case folder) the run may change, add or remove. */
        val changes: Set<String> = emptySet(),
        val stdout: Stdout = Stdout.CAPTURED,
        val storage: Storage = Storage.REAL,
        /** What the command reads as standard input (a FIFO case: what a writer puts into the FIFO). */
        val stdin: ByteArray = ByteArray(0),
        val fifo: Boolean = false,
    )

    private var casesRun = 0
    private var stackTraces = 0
    private var changedOutside = 0
    private var inputsModified = 0

    private val sim = listOf("--duration", "5", "--rate", "50")
    private val table = "t_s,gx,gy,gz,ax,ay,az\n"

    @BeforeAll
    fun buildTemplate() {
        template = Files.createDirectories(tmp.resolve("template"))
        fun t(p: String) = template.resolve(p).toString()
        for (out in listOf("s", "s.zip", "table.csv")) check(fusion("simulate", "-o", t(out), *sim.toTypedArray()).code == 0)
        Files.writeString(template.resolve("prev.csv"), "an earlier output\n")
        Files.writeString(template.resolve("bad.csv"), table + "0,0,0,0,0,0,9.8\n0.01,0,0,0,0,0,9.8\n0.02,0,0,zz,0,0,9.8\n")
        Files.write(template.resolve("corrupt.csv.gz"), byteArrayOf(0x1f, 0x8b.toByte(), 8, 0, 0, 0, 0, 0, 0, 3, 1, 2, 3, 4, 5, 6, 7, 8))
        Files.write(template.resolve("cut.csv.gz"), ByteArrayOutputStream().also { b ->
            java.util.zip.GZIPOutputStream(b).use { it.write((table + "0,0,0,0,0,0,9.8\n".repeat(200)).toByteArray()) }
        }.toByteArray().let { it.copyOf(it.size / 2) })
        Files.writeString(template.resolve("truth.csv"), "t_s,qw,qx,qy,qz\n0,1,0,0,0\n1,1,0,0,0\n")
        // Tables that parse but cannot be right (docs/IMPORT.md, "Plausibility"), made from table.csv.
        val rows = Files.readAllLines(template.resolve("table.csv")).filter { it.isNotBlank() }
        fun variant(name: String, change: (List<MutableList<String>>) -> List<List<String>>) =
            Files.write(template.resolve(name), listOf(rows[0]) + change(rows.drop(1).map { it.split(',').toMutableList() }).map { it.joinToString(",") })
        fun List<MutableList<String>>.time(f: (Double) -> Double) = onEach { it[0] = f(it[0].toDouble()).toString() }
        variant("t-ms.csv") { r -> r.time { it * 1000 } }
        variant("t-reversed.csv") { it.reversed() }
        variant("t-zero.csv") { r -> r.time { 0.0 } }
        variant("t-1hz.csv") { r -> r.time { it * 50 } }
        variant("t-back.csv") { r -> r.onEachIndexed { i, it -> if (i >= r.size / 2) it[0] = (it[0].toDouble() - 3.0).toString() } }
        variant("acc-1e308.csv") { r -> r.also { it[100][6] = "1e308" } }
        variant("gyro-1e30.csv") { r -> r.also { it[100][2] = "1e30" } }
        variant("mag-1e308.csv") { r -> r.also { it[100][7] = "1e308" } }
        variant("mag-zero.csv") { r -> r.onEach { for (k in 7..9) it[k] = "0" } }
        variant("acc-g.csv") { r -> r.onEach { for (k in 4..6) it[k] = (it[k].toDouble() / 9.80665).toString() } }
        check(fusion("simulate", "-o", t("still20"), "--duration", "20", "--rate", "50").code == 0)
        // A session with one accelerometer reading at the largest float.
        val s38 = copyTree(template.resolve("s"), template.resolve("s-3e38"))
        val acc = Files.readAllLines(s38.resolve("accelerometer.csv")).toMutableList()
        acc[60] = acc[60].split(',').toMutableList().also { it[3] = "3.4028235e38" }.joinToString(",")
        Files.write(s38.resolve("accelerometer.csv"), acc)
        // An interrupted session: "complete": false and a partial last row.
        val int = copyTree(template.resolve("s"), template.resolve("s-int"))
        val meta = int.resolve("meta.json")
        Files.writeString(meta, Files.readString(meta).replace("\"complete\": true", "\"complete\": false"))
        Files.write(int.resolve("gyroscope.csv"), "1000005000000,0.1,0.".toByteArray(), java.nio.file.StandardOpenOption.APPEND)
        // ... with a malformed row in the middle.
        val bad = copyTree(int, template.resolve("s-bad"))
        val g = bad.resolve("gyroscope.csv")
        val lines = Files.readAllLines(g)
        Files.write(g, (lines.take(50) + lines[50].replaceFirst(",", ",zz") + lines.drop(51)).joinToString("\n").toByteArray())
        // ... whose meta.json an old in-place write left cut.
        val broken = copyTree(int, template.resolve("s-broken"))
        Files.write(broken.resolve("meta.json"), Files.readAllBytes(broken.resolve("meta.json")).copyOf(60))
        // A foreign project's folder with a format_version but not this project's marker.
        val foreign = Files.createDirectories(template.resolve("foreign"))
        Files.writeString(foreign.resolve("meta.json"), "{\"format_version\": 1, \"complete\": false, \"theirs\": {\"a\": 1}}")
        Files.writeString(foreign.resolve("gyroscope.csv"), "timestamp_ns,x_rad_s,y_rad_s,z_rad_s,accuracy\n1,0,0,0,3\n2,0,")
        Files.createDirectories(template.resolve("outside"))
        Files.writeString(template.resolve("outside/precious.csv"), "timestamp_ns,x_rad_s,y_rad_s,z_rad_s,accuracy\n1,0,0,0,3\n2,0,")
        copyTree(int, template.resolve("s-link"))
        filesAndArchives()
    }

    /** Zips, gzip files and sessions that parse but would read differently in different tools, or lie about being complete. */
    private fun filesAndArchives() {
        val s = template.resolve("s")
        val names = Files.list(s).use { l -> l.map { it.fileName.toString() }.sorted().toList() }
        val gyro = "s/gyroscope.csv".toByteArray()
        fun zipOf(stored: Boolean, extra: List<Pair<String, ByteArray>> = emptyList()): ByteArray = ByteArrayOutputStream().also { o ->
            ZipOutputStream(o).use { z ->
                for ((n, c) in names.map { "s/$it" to Files.readAllBytes(s.resolve(it)) } + extra) {
                    val e = ZipEntry(n)
                    if (stored) {
                        e.method = ZipEntry.STORED
                        e.size = c.size.toLong()
                        e.crc = CRC32().also { it.update(c) }.value
                    }
                    z.putNextEntry(e)
                    z.write(c)
                    z.closeEntry()
                }
            }
        }.toByteArray()
        fun write(name: String, bytes: ByteArray) = Files.write(template.resolve(name), bytes)
        // Two entries named s/gyroscope.csv: the second (a few rows) under another name first, then renamed in both headers.
        val twin = zipOf(false, listOf("s/gyroscopX.csv" to Files.readAllBytes(s.resolve("gyroscope.csv")).copyOf(300)))
        write("dup.zip", replaceAll(twin, "s/gyroscopX.csv".toByteArray(), gyro))
        // The local header of s/gyroscope.csv says otherwise than the central directory.
        val stored = zipOf(true)
        val loc = indexOf(stored, gyro, 0) - 30
        write("loc-name.zip", stored.copyOf().also { it[loc + 30 + 2] = 'G'.code.toByte() })
        write("loc-method.zip", stored.copyOf().also { it[loc + 8] = 8 })
        write("loc-crc.zip", stored.copyOf().also { it[loc + 14] = (it[loc + 14] + 1).toByte() })
        write("loc-size.zip", stored.copyOf().also { it[loc + 22] = (it[loc + 22] - 1).toByte() })
        // A copy of that local entry between the last entry and the central directory: a streaming reader sees it, ZipFile does not.
        val size = Files.size(s.resolve("gyroscope.csv")).toInt()
        val hiddenEntry = stored.copyOfRange(loc, loc + 30 + gyro.size + size)
        val eocd = lastIndexOf(stored, byteArrayOf(0x50, 0x4b, 5, 6))
        val cdOffset = int32(stored, eocd + 16)
        val hidden = stored.copyOfRange(0, cdOffset) + hiddenEntry + stored.copyOfRange(cdOffset, stored.size)
        putInt32(hidden, hidden.size - stored.size + eocd + 16, cdOffset + hiddenEntry.size)
        write("hidden.zip", hidden)
        // The central directory's CRC-32 of a deflated entry (its local header has none: a data descriptor follows the data).
        val deflated = zipOf(false)
        val cen = indexOf(deflated, gyro, indexOf(deflated, gyro, 0) + 1) - 46
        write("cd-crc.zip", deflated.copyOf().also { it[cen + 16] = (it[cen + 16] + 1).toByte() })
        // gzip files of two members (cat a.gz b.gz): whole, a damaged second header, damaged second data, garbage after the first.
        val rows = Files.readAllBytes(template.resolve("table.csv"))
        val half = indexOf(rows, byteArrayOf('\n'.code.toByte()), rows.size / 2) + 1
        val first = gzip(rows.copyOfRange(0, half))
        val second = gzip(rows.copyOfRange(half, rows.size))
        write("two.csv.gz", first + second)
        write("bad-header.csv.gz", first + second.copyOf().also { it[1] = 0 })
        write("bad-data.csv.gz", first + second.copyOf().also { it[12] = (it[12].toInt() xor 0x5a).toByte(); it[13] = (it[13].toInt() xor 0x5a).toByte() })
        write("garbage.csv.gz", first + "not gzip\n".toByteArray())
        write("padded.csv.gz", first + second + ByteArray(64))
        // Complete sessions whose meta.json starts with a UTF-8 BOM, or holds a member nested deeper than the JSON reader's limit.
        val meta = Files.readAllBytes(s.resolve("meta.json"))
        write("bom.csv", byteArrayOf(0xef.toByte(), 0xbb.toByte(), 0xbf.toByte()) + rows)
        Files.write(copyTree(s, template.resolve("s-bom")).resolve("meta.json"), byteArrayOf(0xef.toByte(), 0xbb.toByte(), 0xbf.toByte()) + meta)
        val deep = String(meta).replaceFirst("{", "{\n  \"theirs\": " + "[".repeat(100) + "1" + "]".repeat(100) + ",")
        Files.writeString(copyTree(s, template.resolve("s-deep")).resolve("meta.json"), deep)
        // An interrupted session with a BOM, and one whose cut stream is hard-linked from outside (the link is made per case).
        val int = template.resolve("s-int")
        Files.write(copyTree(int, template.resolve("s-int-bom")).resolve("meta.json"), byteArrayOf(0xef.toByte(), 0xbb.toByte(), 0xbf.toByte()) + Files.readAllBytes(int.resolve("meta.json")))
        copyTree(int, template.resolve("s-hard"))
        Files.createDirectories(template.resolve("elsewhere"))
    }

    private fun gzip(b: ByteArray) = ByteArrayOutputStream().also { o -> java.util.zip.GZIPOutputStream(o).use { it.write(b) } }.toByteArray()

    private fun indexOf(b: ByteArray, what: ByteArray, from: Int): Int =
        (from..b.size - what.size).first { i -> what.indices.all { b[i + it] == what[it] } }

    private fun lastIndexOf(b: ByteArray, what: ByteArray): Int =
        (b.size - what.size downTo 0).first { i -> what.indices.all { b[i + it] == what[it] } }

    private fun replaceAll(b: ByteArray, what: ByteArray, with: ByteArray): ByteArray {
        val out = b.copyOf()
        var i = 0
        while (i <= out.size - what.size) {
            if (what.indices.all { out[i + it] == what[it] }) with.copyInto(out, i)
            i++
        }
        return out
    }

    private fun int32(b: ByteArray, at: Int) = (0 until 4).sumOf { (b[at + it].toInt() and 0xff) shl (8 * it) }

    private fun putInt32(b: ByteArray, at: Int, v: Int) {
        for (k in 0 until 4) b[at + k] = (v ushr (8 * k)).toByte()
    }

    private fun copyTree(from: Path, to: Path): Path {
        Files.walk(from).use { s ->
            for (p in s.toList()) {
                val q = to.resolve(from.relativize(p).toString())
                if (Files.isDirectory(p, LinkOption.NOFOLLOW_LINKS)) Files.createDirectories(q) else Files.copy(p, q, LinkOption.NOFOLLOW_LINKS, StandardCopyOption.COPY_ATTRIBUTES)
            }
        }
        return to
    }

    /** A fresh case folder: the template plus links (copied trees do not keep hard links). */
    private fun caseFolder(name: String): Path {
        val root = copyTree(template, tmp.resolve("case-$name"))
        Files.createSymbolicLink(root.resolve("link.csv"), root.resolve("table.csv"))
        Files.createLink(root.resolve("hard.csv"), root.resolve("table.csv"))
        Files.createSymbolicLink(root.resolve("dangling.csv"), root.resolve("s/new.csv"))
        Files.delete(root.resolve("s-link/gyroscope.csv"))
        Files.createSymbolicLink(root.resolve("s-link/gyroscope.csv"), root.resolve("outside/precious.csv"))
        Files.createSymbolicLink(root.resolve("dangling-out.csv"), Path.of("no-folder/out.csv"))
        Files.createLink(root.resolve("elsewhere/gyroscope.csv"), root.resolve("s-hard/gyroscope.csv"))
        Files.createLink(root.resolve("elsewhere/accelerometer.csv"), root.resolve("s/accelerometer.csv"))
        return root
    }

    private fun hashes(root: Path): Map<String, String> {
        val md = MessageDigest.getInstance("SHA-256")
        return Files.walk(root).use { s ->
            s.filter { it != root }.toList().associate { p ->
                val rel = root.relativize(p).toString()
                val content = when {
                    Files.isDirectory(p) -> "folder"
                    Files.exists(p) -> md.digest(Files.readAllBytes(p)).joinToString("") { "%02x".format(it) } + " modified " + Files.getLastModifiedTime(p, LinkOption.NOFOLLOW_LINKS)
                    else -> "dangling"
                }
                rel to (if (Files.isSymbolicLink(p)) "link → ${Files.readSymbolicLink(p)}: " else "") + content
            }
        }
    }

    private fun cases(): List<Case> {
        val c = ArrayList<Case>()
        val refused = "is the input|lies inside the input"
        // An output that is an input, or inside one, is refused before anything is written.
        c += Case("replay onto its input", listOf("replay", "table.csv", "-o", "table.csv"), 2, refused)
        c += Case("replay into the input session", listOf("replay", "s", "-o", "s/out.csv"), 2, refused)
        c += Case("replay over a stream of the input", listOf("replay", "s", "-o", "s/gyroscope.csv"), 2, refused)
        c += Case("replay onto the input zip", listOf("replay", "s.zip", "-o", "s.zip"), 2, refused)
        c += Case("replay into the input zip", listOf("replay", "s.zip", "-o", "s.zip/x.csv"), 2, refused)
        c += Case("replay onto a symbolic link to the input", listOf("replay", "table.csv", "-o", "link.csv"), 2, refused)
        c += Case("replay onto a hard link to the input", listOf("replay", "table.csv", "-o", "hard.csv"), 2, refused)
        c += Case("replay onto a dangling link into the input", listOf("replay", "s", "-o", "dangling.csv"), 2, refused)
        c += Case("compare onto the input folder", listOf("compare", "s", "-o", "s"), 2, refused)
        c += Case("compare over the input's meta.json", listOf("compare", "s", "-o", "s/meta.json"), 2, refused)
        c += Case("plot onto its input", listOf("plot", "table.csv", "-o", "table.csv"), 2, refused)
        c += Case("plot onto its truth", listOf("plot", "s", "--truth", "truth.csv", "-o", "truth.csv"), 2, refused)
        // A failed run leaves the earlier output as it was.
        c += Case("replay of a malformed table over an earlier output", listOf("replay", "bad.csv", "-o", "prev.csv"), 1, """bad\.csv:4:\d+: column gz""")
        c += Case("replay into a missing folder", listOf("replay", "table.csv", "-o", "missing/out.csv"), 3, """missing/out\.csv: its folder \S*missing does not exist; create it first""")
        c += Case("replay to a full device", listOf("replay", "table.csv", "-o", "/dev/full"), 3, """/dev/full: No space left on device""")
        c += Case("replay on a disk that fills up", listOf("replay", "table.csv", "-o", "prev.csv"), 3, """prev\.csv: No space left on device""", storage = Storage.FULL_AFTER_2000_BYTES)
        c += Case("replay to a folder without permission", listOf("replay", "table.csv", "-o", "prev.csv"), 3, """prev\.csv: permission denied""", storage = Storage.PERMISSION_DENIED)
        c += Case("replay out of memory", listOf("replay", "table.csv", "-o", "prev.csv"), 3, """out of memory: 'replay' needs more than the \d+ MiB""", storage = Storage.OUT_OF_MEMORY)
        c += Case("compare on a disk that fills up", listOf("compare", "s", "-o", "prev.csv"), 3, """prev\.csv: No space left on device""", storage = Storage.FULL_AFTER_2000_BYTES)
        c += Case("plot on a disk that fills up", listOf("plot", "s", "-o", "prev.csv"), 3, """prev\.csv: No space left on device""", storage = Storage.FULL_AFTER_2000_BYTES)
        c += Case("simulate a table on a disk that fills up", listOf("simulate", "-o", "prev.csv") + sim, 3, """prev\.csv: No space left on device""", storage = Storage.FULL_AFTER_2000_BYTES)
        c += Case("simulate a zip on a disk that fills up", listOf("simulate", "-o", "new.zip") + sim, 3, """new\.zip: No space left on device""", storage = Storage.FULL_AFTER_2000_BYTES)
        c += Case("simulate over a session", listOf("simulate", "-o", "s") + sim, 2, """s exists and is not an empty folder""")
        // What succeeds changes exactly its output.
        c += Case("replay to a device", listOf("replay", "table.csv", "-o", "/dev/null"), 0, "")
        c += Case("replay over an earlier output", listOf("replay", "table.csv", "-o", "prev.csv"), 0, "", setOf("prev.csv"))
        c += Case("replay through a link to an earlier output", listOf("replay", "s", "-o", "out-link.csv"), 0, "", setOf("prev.csv", "out-link.csv"))
        c += Case("simulate a new session", listOf("simulate", "-o", "new") + sim, 0, "", setOf("new") + listOf("meta.json", "accelerometer.csv", "gyroscope.csv", "magnetometer.csv", "truth.csv", "rotation_vector.csv").map { "new/$it" })
        // Standard output that cannot be written fails the run (and its file outputs stay aside).
        for (stdout in listOf(Stdout.BROKEN_PIPE, Stdout.DEV_FULL)) {
            val why = if (stdout == Stdout.BROKEN_PIPE) "Broken pipe" else "No space left on device"
            val m = "standard output: $why"
            c += Case("summary, $why", listOf("summary", "table.csv"), 3, m, stdout = stdout)
            c += Case("eval, $why", listOf("eval", "s"), 3, m, stdout = stdout)
            c += Case("compare, $why", listOf("compare", "s"), 3, m, stdout = stdout)
            c += Case("replay to stdout, $why", listOf("replay", "s"), 3, m, stdout = stdout)
            c += Case("simulate, $why", listOf("simulate", "-o", "new.csv") + sim, 3, m, stdout = stdout)
            c += Case("plot, $why", listOf("plot", "s", "-o", "new.svg"), 3, m, stdout = stdout)
            c += Case("recover, $why", listOf("recover", "s-int"), 3, m, setOf("s-int/meta.json", "s-int/gyroscope.csv"), stdout = stdout)
            c += Case("--help, $why", listOf("--help"), 3, m, stdout = stdout)
            c += Case("command help, $why", listOf("replay", "--help"), 3, m, stdout = stdout)
            c += Case("--version, $why", listOf("--version"), 3, m, stdout = stdout)
        }
        // Recovery cannot do harm.
        c += Case("recover a foreign folder", listOf("recover", "foreign"), 1, """foreign/meta\.json: not a Motion Fusion session""")
        c += Case("recover a session with a link out of it", listOf("recover", "s-link"), 1, """s-link/gyroscope\.csv: is a symbolic link""")
        c += Case("recover with a malformed row midway", listOf("recover", "s-bad"), 1, """s-bad/gyroscope\.csv:51:\d+: column""")
        c += Case("recover a zip", listOf("recover", "s.zip"), 2, """not a folder""")
        c += Case("recover nothing", listOf("recover", "nope"), 3, """nope: no such file or folder""")
        c += Case("recover --dry-run", listOf("recover", "--dry-run", "s-int"), 0, "")
        c += Case("recover", listOf("recover", "s-int"), 0, "", setOf("s-int/meta.json", "s-int/gyroscope.csv"))
        c += Case("recover a cut meta.json", listOf("recover", "s-broken"), 0, "", setOf("s-broken/meta.json", "s-broken/meta.json.unreadable", "s-broken/gyroscope.csv"))
        c += Case("recover a complete session", listOf("recover", "s"), 0, "")
        // Usage errors in the tool's own words.
        c += Case("--set of a word as a number", listOf("replay", "table.csv", "--set", "beta=abc"), 2, """--set beta: 'abc' is not a number""")
        c += Case("--set of an unknown mode", listOf("replay", "table.csv", "--set", "mode=fast"), 2, """--set mode: 'fast' is not one of IMU, MARG""")
        c += Case("--set of an unknown setting", listOf("replay", "table.csv", "--set", "nope=1"), 2, """--set nope: no such setting""")
        c += Case("an option given twice", listOf("replay", "table.csv", "--beta", "0.1", "--beta=0.2"), 2, """--beta given twice \('0\.1', then '0\.2'\); give it once""")
        c += Case("an output given under both spellings", listOf("replay", "table.csv", "-o", "a.csv", "--output", "b.csv"), 2, """-o/--output given twice \('.*a\.csv', then '.*b\.csv'\)""")
        c += Case("a setting given twice by --set", listOf("replay", "table.csv", "--set", "beta=0.1", "--set", "headingGain=off,beta=0.2"), 2, """--set beta: beta is already given by --set beta; give it once""")
        c += Case("a setting given by its option and by --set", listOf("replay", "table.csv", "--beta", "0.1", "--set", "beta=0.3"), 2, """--set beta: beta is already given by --beta; give it once""")
        c += Case("--set of a word as a flag", listOf("replay", "table.csv", "--set", "accRejection=yes"), 2, """--set accRejection: 'yes' is not true or false""")
        c += Case("summary of a missing file", listOf("summary", "nope.csv"), 3, """nope\.csv: no such file""")
        c += Case("summary of corrupt gzip data", listOf("summary", "corrupt.csv.gz"), 1, """corrupt\.csv\.gz: corrupt compressed data""")
        c += Case("summary of cut gzip data", listOf("summary", "cut.csv.gz"), 1, """cut\.csv\.gz: compressed data ends early""")
        c += Case("replay of corrupt gzip data", listOf("replay", "corrupt.csv.gz"), 1, """corrupt\.csv\.gz: corrupt compressed data""")
        c += Case("replay of cut gzip data", listOf("replay", "cut.csv.gz"), 1, """cut\.csv\.gz: compressed data ends early""")
        // Inputs that parse but cannot be right: a clear error, or the result without the impossible reading (counted).
        c += Case("replay of a table timed in ms", listOf("replay", "t-ms.csv", "-o", "prev.csv"), 1, """t-ms\.csv: accelerometer: the timestamps imply 0\.05 Hz: the times look like ms, not s""")
        c += Case("replay of a table in reverse order", listOf("replay", "t-reversed.csv", "-o", "prev.csv"), 1, """timestamp steps step back \(rows in reverse order\?\)""")
        c += Case("replay of a table with all times zero", listOf("replay", "t-zero.csv", "-o", "prev.csv"), 1, """timestamp steps are all the same \(0 s\)""")
        c += Case("replay of a 1 Hz table", listOf("replay", "t-1hz.csv", "-o", "prev.csv"), 1, """the timestamps imply 1 Hz""")
        c += Case("replay of a table whose times go back midway", listOf("replay", "t-back.csv", "-o", "prev.csv"), 1, """gyroscope timestamps step back by 2\.980 s .*: the recording is out of order""")
        c += Case("replay of an accelerometer reading of 1e308", listOf("replay", "acc-1e308.csv", "-o", "prev.csv"), 0, """1 beyond any phone's range""", setOf("prev.csv"))
        c += Case("replay of a gyroscope reading of 1e30", listOf("replay", "gyro-1e30.csv", "-o", "prev.csv"), 0, """1 beyond any phone's range""", setOf("prev.csv"))
        c += Case("replay of a magnetometer reading of 1e308", listOf("replay", "mag-1e308.csv", "-o", "prev.csv"), 0, """1 beyond any phone's range""", setOf("prev.csv"))
        c += Case("replay of a session with an accelerometer reading of 3e38", listOf("replay", "s-3e38", "-o", "prev.csv"), 0, """1 beyond any phone's range""", setOf("prev.csv"))
        c += Case("replay of an all-zero magnetometer", listOf("replay", "mag-zero.csv", "-o", "prev.csv"), 1, """magnetometer: is zero throughout: no field was recorded; replay in 6D \(--mode 6d\)""")
        c += Case("replay of an accelerometer in g", listOf("replay", "acc-g.csv", "-o", "prev.csv"), 1, """accelerometer: looks like g, not m/s²""")
        c += Case("--beta 1e308", listOf("replay", "table.csv", "--beta", "1e308"), 2, """--beta: beta must be within 0–50 rad/s: 1\.0E308""")
        c += Case("--max-gap 1e9", listOf("replay", "table.csv", "--max-gap", "1e9"), 2, """--max-gap: maxGap must be within 0–200 s""")
        c += Case("--set of a setting far out of range", listOf("replay", "table.csv", "--set", "magNormTolerance=1e6"), 2, """--set magNormTolerance: magNormTolerance must be within 0–50""")
        c += Case("allan on 20 s", listOf("allan", "still20", "-o", "prev.csv"), 1, """still20: 20\.0 s of samples is too short for noise figures: the noise density needs at least 60 s""")
        c += filesAndArchivesCases()
        return c
    }

    /** Archives that lie, inputs that are not plain files, recovery of sessions that are complete or linked (docs/IMPORT.md, "Files and archives"). */
    private fun filesAndArchivesCases(): List<Case> {
        val c = ArrayList<Case>()
        val differ = "its local header and the zip's central directory disagree"
        c += Case("replay of a zip with two entries of one name", listOf("replay", "dup.zip"), 1, """dup\.zip!/s/gyroscope\.csv: the zip holds two entries of this name""")
        c += Case("replay of a zip whose local header names another file", listOf("replay", "loc-name.zip"), 1, """loc-name\.zip!/s/gyroscope\.csv: $differ \(name 's/Gyroscope\.csv'\)""")
        c += Case("replay of a zip whose local header has another method", listOf("replay", "loc-method.zip"), 1, """loc-method\.zip!/s/gyroscope\.csv: $differ \(compression method""")
        c += Case("replay of a zip whose local header has another CRC-32", listOf("replay", "loc-crc.zip"), 1, """loc-crc\.zip!/s/gyroscope\.csv: $differ \(CRC-32""")
        c += Case("replay of a zip whose local header has another size", listOf("replay", "loc-size.zip"), 1, """loc-size\.zip!/s/gyroscope\.csv: $differ \(size \d+ or \d+ bytes""")
        c += Case("replay of a zip with an entry the central directory leaves out", listOf("replay", "hidden.zip"), 1, """hidden\.zip: bytes \d+ to \d+ lie in no entry of the central directory""")
        c += Case("replay of a zip whose central directory has another CRC-32", listOf("replay", "cd-crc.zip"), 1, """cd-crc\.zip!/s/gyroscope\.csv: corrupt compressed data: CRC-32 \w+ of the data differs""")
        c += Case("replay of a gzip file of two members", listOf("replay", "two.csv.gz", "-o", "prev.csv"), 0, "", setOf("prev.csv"))
        c += Case("summary of a gzip file of two members", listOf("summary", "two.csv.gz"), 0, "")
        c += Case("replay of a gzip file with zero padding", listOf("replay", "padded.csv.gz"), 0, "")
        c += Case("replay of a gzip file whose second header is damaged", listOf("replay", "bad-header.csv.gz"), 1, """bad-header\.csv\.gz: corrupt compressed data: member 2 \(at byte \d+\): not a gzip header""")
        c += Case("replay of a gzip file whose second member's data is damaged", listOf("replay", "bad-data.csv.gz"), 1, """bad-data\.csv\.gz: corrupt compressed data: member 2""")
        c += Case("summary of a gzip file with garbage after its member", listOf("summary", "garbage.csv.gz"), 1, """garbage\.csv\.gz: corrupt compressed data: member 2 \(at byte \d+\): not a gzip header""")
        // Standard input, FIFOs, devices.
        val table = Files.readAllBytes(template.resolve("table.csv"))
        c += Case("summary of standard input", listOf("summary", "-"), 0, "", stdin = table)
        c += Case("replay of standard input", listOf("replay", "-", "-o", "prev.csv"), 0, "", setOf("prev.csv"), stdin = table)
        c += Case("replay of gzip data on standard input", listOf("replay", "-"), 0, "", stdin = gzip(table))
        c += Case("replay of a session zip on standard input", listOf("replay", "-"), 0, "", stdin = Files.readAllBytes(template.resolve("s.zip")))
        c += Case("replay of a malformed table on standard input", listOf("replay", "-"), 1, """standard input:4:\d+: column gz""", stdin = Files.readAllBytes(template.resolve("bad.csv")))
        c += Case("replay of an empty standard input", listOf("replay", "-"), 1, """standard input: empty: nothing was read from it""")
        c += Case("replay of /dev/null", listOf("replay", "/dev/null"), 1, """/dev/null: empty: nothing was read from it""")
        c += Case("summary of /dev/null", listOf("summary", "/dev/null"), 1, """/dev/null:1: empty file""")
        c += Case("replay of a FIFO", listOf("replay", "FIFO"), 0, "", stdin = table, fifo = true)
        c += Case("summary of a FIFO", listOf("summary", "FIFO"), 0, "", stdin = table, fifo = true)
        c += Case("replay of a session zip through a FIFO", listOf("replay", "FIFO"), 0, "", stdin = Files.readAllBytes(template.resolve("s.zip")), fifo = true)
        // Folders where a file is expected; links and paths named as given.
        c += Case("summary of a folder", listOf("summary", "s"), 3, """/s: is a folder; a file is expected here""")
        c += Case("eval with a folder as truth", listOf("eval", "--truth", "s", "truth.csv"), 3, """/s: is a folder; a file is expected here""")
        c += Case("replay to a folder", listOf("replay", "table.csv", "-o", "outside"), 3, """/outside: is a folder; give the name of a file to write""")
        c += Case("replay onto a dangling link", listOf("replay", "table.csv", "-o", "dangling-out.csv"), 3, """/dangling-out\.csv: a link to no-folder/out\.csv, whose folder does not exist""")
        val long = "./".repeat(2100)
        c += Case("replay of a path over the system's limit", listOf("replay", long + "table.csv"), 3, """…\(\d+ characters\)….*/table\.csv: path too long""")
        c += Case("summary of a name over the system's limit", listOf("summary", "t".repeat(300) + ".csv"), 3, """t{20}.*: path too long""")
        c += Case("recover a path over the system's limit", listOf("recover", long + "s-int"), 3, """path too long""")
        c += Case("replay to a path over the system's limit", listOf("replay", "table.csv", "-o", long + "prev.csv"), 0, "", setOf("prev.csv"))
        // Recovery never rewrites a complete session nor changes a hard-linked stream in place.
        c += Case("recover a complete session whose meta.json has a BOM", listOf("recover", "s-bom"), 0, "")
        c += Case("replay a session whose meta.json has a BOM", listOf("replay", "s-bom", "-o", "prev.csv"), 0, "", setOf("prev.csv"))
        c += Case("summary of a table with a BOM", listOf("summary", "bom.csv"), 0, "")
        c += Case("recover a complete session whose meta.json is nested deeply", listOf("recover", "s-deep"), 1, """s-deep/meta\.json:2:\d+: nested deeper than 64 levels: not a meta\.json cut short, so not rebuilt; left untouched""")
        c += Case("recover an interrupted session whose meta.json has a BOM", listOf("recover", "s-int-bom"), 0, "", setOf("s-int-bom/meta.json", "s-int-bom/gyroscope.csv"))
        c += Case("recover a session with a hard-linked cut stream", listOf("recover", "s-hard"), 0, "", setOf("s-hard/meta.json", "s-hard/gyroscope.csv"))
        c += Case("recover a complete session with a hard-linked stream", listOf("recover", "s"), 0, "")
        return c
    }

    @TestFactory
    fun `hostile runs of fusion`(): List<DynamicTest> = cases().map { case -> DynamicTest.dynamicTest(case.name) { run(case) } }

    private fun run(case: Case) {
        val root = caseFolder(case.name.replace(Regex("[^A-Za-z0-9]+"), "-"))
        if (case.name == "replay through a link to an earlier output") Files.createSymbolicLink(root.resolve("out-link.csv"), root.resolve("prev.csv"))
        val before = hashes(root)
        // A FIFO lies outside the case folder (hashing it would wait for a writer); a thread writes into it.
        val fifo = if (case.fifo) tmp.resolve("fifo-" + root.fileName).also { check(ProcessBuilder("mkfifo", it.toString()).start().waitFor() == 0) } else null
        val writer = fifo?.let { f -> Thread { runCatching { Files.write(f, case.stdin) } }.apply { isDaemon = true; start() } }
        val args = case.args.mapIndexed { i, a -> if (a == "FIFO" && fifo != null) fifo.toString() else if (isPath(case.args, i)) root.resolve(a).toString() else a }
        val err = ByteArrayOutputStream()
        val captured = ByteArrayOutputStream()
        val raw: OutputStream = when (case.stdout) {
            Stdout.CAPTURED -> captured
            Stdout.BROKEN_PIPE -> object : OutputStream() {
                override fun write(b: Int) = throw IOException("Broken pipe")
            }
            Stdout.DEV_FULL -> FileOutputStream("/dev/full")
        }
        val recording = RecordingOutput(raw)
        val stdin = System.`in`
        System.setIn(java.io.ByteArrayInputStream(if (case.fifo) ByteArray(0) else case.stdin))
        val code = try {
            raw.use {
                Cli(PrintStream(recording, false, "UTF-8"), PrintStream(err, true, "UTF-8"), Outputs(storage(case.storage)), { recording.failure }).run(args)
            }
        } finally {
            System.setIn(stdin)
        }
        writer?.join()
        val message = err.toString("UTF-8")
        casesRun++
        if (message.contains("\tat ") || message.contains("Exception")) stackTraces++
        val after = hashes(root)
        val changed = (before.keys + after.keys).filter { before[it] != after[it] }.toSet()
        val outside = changed - case.changes
        changedOutside += outside.size
        val inputs = case.args.indices.filter { isPath(case.args, it) && case.args.getOrNull(it - 1) != "-o" }.map { case.args[it] }.toSet()
        val inputsChanged = outside.filter { c -> inputs.any { c == it || c.startsWith("$it/") } }
        inputsModified += inputsChanged.size
        println("${case.name}: exit $code; ${message.lines().lastOrNull { it.isNotBlank() } ?: ""}".replace(root.toString() + "/", ""))

        assertEquals(case.code, code, "exit code; stderr: $message")
        assertTrue(Regex(case.message).containsMatchIn(message), "message /${case.message}/ in: $message")
        assertTrue(!message.contains("\tat ") && !message.contains("Exception"), "no stack trace: $message")
        assertEquals(emptyList<String>(), inputsChanged, "inputs modified")
        assertEquals(emptySet<String>(), outside, "changed outside the expected output ${case.changes}")
        if (case.code == 0 && case.changes.isNotEmpty()) assertEquals(case.changes.filter { !it.startsWith("new/") }.toSet(), changed.filter { !it.startsWith("new/") }.toSet(), "the output is in place")
    }

    private fun storage(s: Storage): FileOperations = when (s) {
        Storage.REAL -> FileOperations.SYSTEM
        Storage.FULL_AFTER_2000_BYTES -> FullDisk(2000)
        Storage.PERMISSION_DENIED -> object : FileOperations by FileOperations.SYSTEM {
            override fun create(path: Path): SyncedOutput = throw AccessDeniedException(path.toString())
        }
        Storage.OUT_OF_MEMORY -> object : FileOperations by FileOperations.SYSTEM {
            override fun create(path: Path): SyncedOutput = throw OutOfMemoryError("Java heap space")
        }
    }

    @AfterAll
    fun numbers() {
        tmp.toFile().deleteRecursively()
        println("hostile cases: $casesRun run, $stackTraces stack traces, $changedOutside files changed outside their targets, $inputsModified inputs modified")
    }

    /** True when args[i] names a file of the case folder (not the command, an option, an option's value or an absolute path). */
    private fun isPath(args: List<String>, i: Int): Boolean {
        val a = args[i]
        return i > 0 && !a.startsWith("-") && !a.startsWith("/") && args[i - 1] !in VALUE_OPTIONS
    }

    private companion object {
        val VALUE_OPTIONS = setOf("--duration", "--rate", "--seed", "--set", "--angles", "--beta", "--max-gap")
    }
}

/** Storage that takes [spaceBytes] bytes in all and then fails like a full disk (write(2): ENOSPC). */
internal class FullDisk(private val spaceBytes: Long) : FileOperations by FileOperations.SYSTEM {
    private var written = 0L

    override fun create(path: Path): SyncedOutput {
        val out = FileOperations.SYSTEM.create(path)
        return object : SyncedOutput() {
            override fun write(b: Int) = write(byteArrayOf(b.toByte()), 0, 1)

            override fun write(b: ByteArray, off: Int, len: Int) {
                val n = minOf(len.toLong(), maxOf(0L, spaceBytes - written)).toInt()
                if (n > 0) out.write(b, off, n)
                written += n
                if (n < len) throw IOException("No space left on device")
            }

            override fun sync() = out.sync()
            override fun close() = out.close()
        }
    }
}
