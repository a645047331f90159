// fusion-core: pure Kotlin on the JVM, no android.* (fusion-core/pom.xml).
plugins {
    alias(libs.plugins.kotlin.jvm)
}

kotlin {
    jvmToolchain(17)
    // As -Xexplicit-api=strict in fusion-core/pom.xml (main sources only).
    explicitApi()
    compilerOptions {
        freeCompilerArgs.add("-Xjsr305=strict")
    }
}

sourceSets {
    main { kotlin.srcDirs("src/main/kotlin") }
    test { kotlin.srcDirs("src/test/kotlin") }
}

dependencies {
    implementation(libs.kotlin.stdlib)
    testImplementation(platform(libs.junit.bom))
    testImplementation(libs.junit.jupiter)
    testRuntimeOnly(libs.junit.platform.launcher)
    // The real SensorManager, to test the ports against.
    testImplementation(libs.android.all)
}

// As Surefire in pom.xml and fusion-core/pom.xml: the same JVM heap and system properties.
tasks.test {
    useJUnitPlatform()
    maxHeapSize = "2g"
    // PublicApiTest lists the API from the compiled main classes (Maven: target/classes).
    systemProperty("api.classes", sourceSets.main.get().output.classesDirs.asPath)
}
