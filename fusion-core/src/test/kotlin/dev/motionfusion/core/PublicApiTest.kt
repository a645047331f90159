package dev.motionfusion.core

import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import java.io.File
import java.lang.reflect.Constructor
import java.lang.reflect.Executable
import java.lang.reflect.Member
import java.lang.reflect.Method
import java.lang.reflect.Modifier

/**
 * The public API of fusion-core, listed from the compiled main classes and compared
 * with the committed listing `api/fusion-core.api`, so that every change of the API is a visible
 * diff in review. After an intended change, regenerate the listing with
 *
 *     mvn -B -pl fusion-core test -Dtest=PublicApiTest -Dsurefire.failIfNoSpecifiedTests=false -Dapi.update=true
 *
 * and commit it (fusion-stream's listing likewise: `-pl fusion-core,fusion-stream`, `-Dtest=StreamApiTest`). What is listed: every class whose Kotlin visibility is public or protected (read
 * from its @Metadata, since `internal` is public to the JVM), and its public and protected
 * constructors, methods and fields, except synthetic ones, members mangled by Kotlin for
 * `internal` (their JVM names carry `$`), `internal` top-level functions and constants, and
 * constructors Kotlin declares `internal`.
 *
 * The build names the folder of the compiled main classes in the system property `api.classes`
 * (Maven: target/classes; Gradle: its class output folders, separated by the path separator); a run
 * without it, or with no compiled classes there, fails rather than skipping the check.
 */
class PublicApiTest {
    private val classes: File = PublicApi.classesOf("dev/motionfusion/core")

    @Test
    fun `the public API equals the committed listing`() {
        PublicApi.check(classes, File("api/fusion-core.api"), "fusion-core")
    }

    @Test
    fun `the metadata reader sees internal and public as Kotlin declares them`() {
        val text = PublicApi.listing(classes)
        assertTrue("class dev.motionfusion.core.Quaternion" in text, "a public class is listed")
        assertTrue("dev.motionfusion.core.io.ByteCsvReader" !in text, "an internal class is not listed")
        assertTrue("quaternionToMatrix" !in text, "an internal top-level function is not listed")
        assertTrue("setTimeS" !in text, "an internal setter (mangled) is not listed")
        assertTrue("ReplayStep()" !in text, "an internal constructor is not listed")
        assertTrue("public static final dev.motionfusion.core.AndroidAngles androidOrientation(dev.motionfusion.core.RotationMatrix)" in text, "a public top-level function is listed")
    }
}

/**
 * Builds the listing from compiled classes and compares it with a module's committed one (see
 * PublicApiTest; fusion-stream's StreamApiTest uses it through fusion-core's test jar).
 */
object PublicApi {
    /**
     * The folder of the compiled main classes the build names in the system property `api.classes`
     * (several separated by the path separator), the one that holds [packageDir]; fails without it.
     */
    fun classesOf(packageDir: String): File {
        val given = System.getProperty("api.classes")
        assertTrue(!given.isNullOrEmpty(), "system property api.classes not set (the build sets it: the module's pom.xml and build.gradle.kts)")
        val dirs = given.split(File.pathSeparatorChar).filter { it.isNotEmpty() }.map(::File)
        return dirs.firstOrNull { File(it, packageDir).isDirectory }
            ?: throw AssertionError("no compiled classes of $packageDir in api.classes=$given")
    }

    /**
     * Fails, with the differing lines, when the listing of [classesDir] differs from [listing];
     * with the system property `api.update=true` it writes [listing] instead.
     */
    fun check(classesDir: File, listing: File, module: String) {
        val actual = listing(classesDir)
        if (System.getProperty("api.update") == "true") {
            listing.parentFile.mkdirs()
            listing.writeText(actual)
            return
        }
        val expected = if (listing.isFile) listing.readText() else ""
        if (expected == actual) return
        val e = expected.lines().toSet()
        val a = actual.lines().toSet()
        val diff = buildString {
            for (line in expected.lines()) if (line !in a) appendLine("- $line")
            for (line in actual.lines()) if (line !in e) appendLine("+ $line")
        }
        val modules = if (module == "fusion-core") module else "fusion-core,$module"
        val update = "mvn -B -pl $modules test -Dtest=PublicApiTest,StreamApiTest -Dsurefire.failIfNoSpecifiedTests=false -Dapi.update=true"
        assertTrue(
            false,
            "The public API of $module differs from ${listing.path} (- listed, + compiled):\n$diff\n" +
                "If the change is intended, regenerate the listing and commit it:\n  $update",
        )
    }

    fun listing(classesDir: File): String {
        val loader = Thread.currentThread().contextClassLoader
        val names = classesDir.walk().filter { it.isFile && it.name.endsWith(".class") }
            .map { it.relativeTo(classesDir).path.removeSuffix(".class").replace(File.separatorChar, '.') }
            .sorted().toList()
        val out = StringBuilder()
        for (name in names) {
            val c = Class.forName(name, false, loader)
            if (!isApi(c)) continue
            val meta = KotlinMetadata.of(c)
            val members = ArrayList<String>()
            val publicConstructors = meta?.constructorVisibilities?.count { it.isApi() }
            for (k in c.declaredConstructors) {
                if (!visible(k) || publicConstructors == 0) continue
                members += "  " + signature(k)
            }
            for (m in c.declaredMethods) {
                if (!visible(m) || m.isBridge) continue
                if (meta != null && meta.kind != 1 && meta.memberVisibility[m.name]?.isApi() == false) continue
                members += "  " + signature(m)
            }
            // A companion's constants are fields of the class; their visibility is the companion's and its own.
            val companionClass = c.declaredClasses.firstOrNull { it.simpleName == "Companion" }
            val companion = companionClass?.let(KotlinMetadata::of)
            for (f in c.declaredFields) {
                if (!visible(f)) continue
                val inCompanion = meta?.memberVisibility?.get(f.name) == null && companion?.memberVisibility?.get(f.name) != null
                if (inCompanion && !isApi(companionClass!!)) continue
                val v = meta?.memberVisibility?.get(f.name) ?: companion?.memberVisibility?.get(f.name)
                if (v?.isApi() == false) continue
                members += "  " + modifiers(f.modifiers) + f.genericType.typeName + " " + f.name
            }
            if (members.isEmpty() && meta != null && meta.kind != 1) continue // a file of internal declarations only
            out.append(classLine(c)).append(" {\n")
            members.sorted().forEach { out.append(it).append('\n') }
            out.append("}\n\n")
        }
        return out.toString()
    }

    private fun Int.isApi() = this == PUBLIC || this == PROTECTED

    private fun isApi(c: Class<*>): Boolean {
        if (c.isSynthetic || c.isAnonymousClass || c.isLocalClass) return false
        if (!(Modifier.isPublic(c.modifiers) || Modifier.isProtected(c.modifiers))) return false
        val meta = KotlinMetadata.of(c)
        if (meta != null && (meta.kind == 3 || !meta.classVisibility.isApi())) return false
        return c.declaringClass?.let(::isApi) ?: true
    }

    private fun visible(m: Member): Boolean =
        (Modifier.isPublic(m.modifiers) || Modifier.isProtected(m.modifiers)) && !m.isSynthetic && '$' !in m.name &&
            (m !is Executable || m.parameterTypes.all(::typeIsApi))

    private fun typeIsApi(t: Class<*>): Boolean {
        var c = t
        while (c.isArray) c = c.componentType
        return !c.name.startsWith("dev.motionfusion.") || isApi(c)
    }

    private fun modifiers(m: Int): String = Modifier.toString(m and (Modifier.PUBLIC or Modifier.PROTECTED or Modifier.STATIC or Modifier.FINAL or Modifier.ABSTRACT)).let { if (it.isEmpty()) it else "$it " }

    private fun classLine(c: Class<*>): String {
        val kind = when {
            c.isAnnotation -> "annotation"
            c.isInterface -> "interface"
            c.isEnum -> "enum"
            else -> "class"
        }
        val mods = modifiers(if (c.isInterface) c.modifiers and Modifier.ABSTRACT.inv() else c.modifiers)
        val supers = listOfNotNull(c.genericSuperclass?.typeName?.takeIf { it != "java.lang.Object" && !c.isEnum }) +
            c.genericInterfaces.map { it.typeName }
        return "$mods$kind ${c.name}" + if (supers.isEmpty()) "" else " : " + supers.joinToString(", ")
    }

    private fun signature(e: Executable): String {
        val params = e.genericParameterTypes.joinToString(", ") { it.typeName }
        return when (e) {
            is Constructor<*> -> modifiers(e.modifiers) + e.declaringClass.simpleName + "($params)"
            is Method -> modifiers(e.modifiers) + e.genericReturnType.typeName + " " + e.name + "($params)"
            else -> error(e)
        }
    }

    private const val PUBLIC = 3
    private const val PROTECTED = 2
}

/**
 * The little of a class's @kotlin.Metadata the listing needs: the kind, the Kotlin visibility of
 * the class, of its constructors, and of its functions and properties by name. A minimal reader
 * of the protobuf messages the Kotlin compiler writes (kotlin/metadata.proto: Class, Package,
 * Constructor, Function, Property; flags with the visibility in bits 1–3).
 */
internal class KotlinMetadata(
    val kind: Int,
    val classVisibility: Int,
    val constructorVisibilities: List<Int>,
    val memberVisibility: Map<String, Int>,
) {
    companion object {
        fun of(c: Class<*>): KotlinMetadata? {
            val m = c.getAnnotation(Metadata::class.java) ?: return null
            if (m.kind != 1 && m.kind != 2 && m.kind != 5) return KotlinMetadata(m.kind, 3, emptyList(), emptyMap())
            val bytes = decode(m.data1)
            val r = Proto(bytes, 0, bytes.size)
            // A length-delimited StringTableTypes comes first.
            val tableLength = r.varint().toInt()
            r.pos += tableLength
            val ctors = ArrayList<Int>()
            val members = HashMap<String, Int>()
            var classFlags = 6
            val (functionField, propertyField) = if (m.kind == 1) 9 to 10 else 3 to 4
            r.fields { field, sub ->
                when {
                    m.kind == 1 && field == 1 && sub == null -> classFlags = r.last.toInt()
                    m.kind == 1 && field == 8 && sub != null -> ctors += flagsOf(sub, listOf(1), 6)
                    field == functionField && sub != null -> nameAndFlags(sub, listOf(9, 1), 6, m.data2)?.let { (n, f) -> members.merge(n, f, ::maxOf) }
                    field == propertyField && sub != null -> nameAndFlags(sub, listOf(11, 1), 518, m.data2)?.let { (n, f) ->
                        members.merge(n, f, ::maxOf)
                        val cap = n.replaceFirstChar { it.uppercaseChar() }
                        members.merge("get$cap", f, ::maxOf)
                        members.merge("set$cap", f, ::maxOf)
                        if (n.startsWith("is")) members.merge(n, f, ::maxOf)
                    }
                }
            }
            return KotlinMetadata(m.kind, visibility(classFlags), ctors.map(::visibility), members)
        }

        private fun visibility(flags: Int) = (flags shr 1) and 7

        private fun flagsOf(p: Proto, fields: List<Int>, default: Int): Int {
            val found = HashMap<Int, Int>()
            p.fields { f, sub -> if (sub == null && f in fields) found[f] = p.last.toInt() }
            return fields.firstNotNullOfOrNull { found[it] } ?: default
        }

        private fun nameAndFlags(p: Proto, flagFields: List<Int>, default: Int, strings: Array<String>): Pair<String, Int>? {
            val found = HashMap<Int, Long>()
            p.fields { f, sub -> if (sub == null) found[f] = p.last }
            val name = found[2]?.toInt()?.let { strings.getOrNull(it) } ?: return null
            val flags = flagFields.firstNotNullOfOrNull { found[it]?.toInt() } ?: default
            return name to visibility(flags)
        }

        /** d1 as bytes: the compiler's "UTF-8 mode" (a leading U+0000, one char per byte), or 8-to-7 bit packing. */
        private fun decode(d1: Array<String>): ByteArray {
            require(d1.isNotEmpty() && d1[0].isNotEmpty() && d1[0][0] == '\u0000') { "unsupported metadata encoding" }
            val s = d1.joinToString("").substring(1)
            return ByteArray(s.length) { s[it].code.toByte() }
        }
    }

    /** Protobuf wire format over bytes[from, to). */
    private class Proto(val b: ByteArray, var pos: Int, val end: Int) {
        var last = 0L

        fun varint(): Long {
            var shift = 0
            var result = 0L
            while (true) {
                val x = b[pos++].toInt()
                result = result or ((x and 0x7f).toLong() shl shift)
                if (x and 0x80 == 0) return result
                shift += 7
            }
        }

        /** Calls [each] with (field, null) for scalars (value in [last]) and (field, reader) for length-delimited fields. */
        fun fields(each: (Int, Proto?) -> Unit) {
            while (pos < end) {
                val tag = varint().toInt()
                val field = tag ushr 3
                when (tag and 7) {
                    0 -> { last = varint(); each(field, null) }
                    1 -> pos += 8
                    2 -> {
                        val len = varint().toInt()
                        val start = pos
                        pos += len
                        each(field, Proto(b, start, start + len))
                    }
                    5 -> pos += 4
                    else -> error("wire type ${tag and 7}")
                }
            }
        }
    }
}
